"""What vector code this CPU runs: the widest vector instructions it offers, and what the
projection kernel (grid_sweeps.sweep_grid_colors) compiles to here.

numba keeps no assembly for kernels loaded from its cache, so the kernel's is read from a
fresh compile of the same function for the signature the run used (seconds: full benches
only). LLVM may choose narrower vectors than the CPU offers (on Intel server cores it
prefers 256-bit ones), so the compiled registers, not the CPU's flags, say what runs."""

from __future__ import annotations

import re
from collections import Counter

FLOAT_OPS = re.compile(r"v?(sqrt|div|mul|add|sub|fn?m(?:add|sub)\d*)([ps])d")
REGISTER_BITS = {"zmm": 512, "ymm": 256, "xmm": 128}


def cpu_vectors() -> dict:
    """LLVM's name for the host CPU and the widest vector registers its features allow."""
    import llvmlite.binding as ll

    features = {k for k, v in ll.get_host_cpu_features().items() if v}
    bits = 512 if "avx512f" in features else 256 if "avx" in features else 128
    return {"llvm_cpu": ll.get_host_cpu_name(), "isa_vector_bits": bits,
            "fma": "fma" in features}


def count_float_ops(asm: str) -> dict:
    """Double-precision arithmetic instructions in `asm`, by kind and register width."""
    counts: Counter = Counter()
    for line in asm.splitlines():
        parts = line.split(None, 1)
        if len(parts) != 2:
            continue
        op, args = parts
        m = FLOAT_OPS.fullmatch(op)
        if not m:
            continue
        reg = next((r for r in REGISTER_BITS if r in args), "xmm")
        if m.group(2) == "s":
            counts["scalar"] += 1
        else:
            counts[f"packed_{REGISTER_BITS[reg]}"] += 1
    return dict(counts)


def projection_kernel_ops() -> dict:
    """count_float_ops of the serial sweep kernel as compiled on this machine, for the
    signature a run already used; {} if it has not run in this process."""
    from numba import njit

    from ..sim.grid_sweeps import sweep_grid_colors
    from ..sim.jit import KERNEL_OPTIONS

    if not sweep_grid_colors.signatures:
        return {}
    sig = sweep_grid_colors.signatures[0]
    fresh = njit(**{**KERNEL_OPTIONS, "cache": False, "_nrt": False})(
        sweep_grid_colors.py_func)
    fresh.compile(sig)
    return count_float_ops(fresh.inspect_asm(sig))


def describe(cpu: dict, ops: dict | None) -> str:
    line = (f"vectors: the CPU offers {cpu['isa_vector_bits']}-bit (LLVM target "
            f"{cpu['llvm_cpu']}{', FMA' if cpu['fma'] else ''})")
    if ops:
        packed = sorted((k for k in ops if k.startswith("packed")), reverse=True)
        line += ("; the projection kernel compiles to " + ", ".join(
            f"{ops[k]} {k.split('_')[1]}-bit packed" for k in packed)
            + f" and {ops.get('scalar', 0)} scalar double ops")
    return line
