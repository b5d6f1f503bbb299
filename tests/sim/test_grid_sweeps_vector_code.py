"""The projection kernel compiles to vector code on this CPU: the sweeps' speed rests on it,
and a harmless-looking change to the pair loop (a branch on `alive`, the loop inlined into
its caller) once left it all scalar without a test noticing."""

from __future__ import annotations

import platform

import pytest

from cloth_tui.bench.step_bench import bare_scene
from cloth_tui.bench.vector_code import count_float_ops, projection_kernel_ops
from cloth_tui.sim.model import build_model
from cloth_tui.sim.state import ClothState
from cloth_tui.sim.solvers.xpbd.constraints import ProjectConstraints

pytestmark = pytest.mark.skipif(platform.machine() not in ("x86_64", "AMD64"),
                                reason="count_float_ops reads x86 assembly")


def test_count_float_ops_tells_packed_from_scalar():
    asm = "\tvmulpd\t%ymm1, %ymm2, %ymm3\n\tvsqrtpd %xmm0, %xmm1\n\tvaddsd %xmm0, %xmm1, %xmm2\n"
    assert count_float_ops(asm) == {"packed_256": 1, "packed_128": 1, "scalar": 1}


def test_the_sweep_kernel_compiles_to_vector_code():
    """Packed arithmetic at whatever width LLVM picks for this CPU (128, 256 or 512 bits
    all count): a loop that stops vectorising compiles to scalar ops only."""
    scene = bare_scene(32)
    model = build_model(scene.cloth, scene.behavior)
    state = ClothState.from_model(model)
    ProjectConstraints(model, 2, 0.0, 1 / 240, "project_constraints").apply(state, 1 / 240)
    ops = projection_kernel_ops()
    packed = sum(n for kind, n in ops.items() if kind.startswith("packed_"))
    assert packed >= 20, ops
