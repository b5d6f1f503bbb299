"""Compiler settings shared by every numba kernel in `sim/`.

FASTMATH lets LLVM reorder and fuse arithmetic (the speed of `fastmath=True`) but leaves out
its `nnan` and `ninf` flags: under those, `math.isfinite(nan)` compiles to True and NaN
checks vanish (issue 12 item 3). With this set a kernel still sees NaN and infinity.
"""

FASTMATH = {"nsz", "arcp", "contract", "afn", "reassoc"}
