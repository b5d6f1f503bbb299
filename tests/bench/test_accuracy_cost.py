"""The cost-of-accuracy table's pieces: the growth fit and the kernel's instruction count."""

import math

from cloth_tui.bench.accuracy_cost import growth_exponent
from cloth_tui.bench.vector_code import count_float_ops, describe


def test_growth_exponent_is_the_log_log_slope_over_the_chosen_sizes():
    rows = [{"n": n, "particles": n * n, "ms_per_frame": 0.01 * (n * n) ** 1.5}
            for n in (32, 64, 128, 256)]
    rows[0]["ms_per_frame"] *= 10  # off the line: left out by lo=64
    assert math.isclose(growth_exponent(rows, lo=64, hi=256), 1.5)
    assert growth_exponent(rows) < 1.5
    assert growth_exponent(rows[:1]) is None


def test_float_ops_are_counted_by_register_width():
    asm = """
        vmulpd  %ymm1, %ymm2, %ymm3
        vfmadd231pd %zmm1, %zmm2, %zmm3
        vsqrtsd %xmm0, %xmm0, %xmm0
        vaddpd  %xmm1, %xmm2, %xmm3
        vmovupd (%rax), %ymm0
        addq    $8, %rax
    """
    ops = count_float_ops(asm)
    assert ops == {"packed_256": 1, "packed_512": 1, "scalar": 1, "packed_128": 1}
    text = describe({"isa_vector_bits": 512, "llvm_cpu": "znver1", "fma": True}, ops)
    assert "512-bit packed" in text and "1 scalar" in text and "znver1" in text
