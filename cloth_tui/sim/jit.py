"""Compiler settings shared by every numba kernel in `sim/`: use `@kernel(...)`, not `@njit`.

FASTMATH lets LLVM reorder arithmetic (most of the speed of `fastmath=True`) but leaves out
its `nnan` and `ninf` flags: under those, `math.isfinite(nan)` compiles to True and NaN
checks vanish. With this set a kernel still sees NaN and infinity. It leaves out `contract`
(a multiply and an add fused into one rounding) too: with it, a kernel compiled in this
process and the same kernel loaded from numba's cache rounded differently (multigrid's
v_cycle, found when a cold-cache test process and its Dask workers, which load the cache
that process wrote, disagreed on a jittering lbfgs strip). A run must give the same numbers
wherever and whenever it runs.

error_model="numpy": a float division by zero gives ±inf or NaN as in NumPy instead of raising
ZeroDivisionError (numba's default, the Python model). A diverging frame can drive a distance
to exactly zero inside any kernel; it must come out as a non-finite state that the runner's
guard sees, undoes and retries, not as an exception that kills the simulation thread.
"""

from numba import njit

FASTMATH = {"nsz", "arcp", "afn", "reassoc"}
KERNEL_OPTIONS = {"nogil": True, "cache": True, "fastmath": FASTMATH, "error_model": "numpy"}


def kernel(**options):
    """`numba.njit` with KERNEL_OPTIONS; `options` add to or override them."""
    return njit(**{**KERNEL_OPTIONS, **options})
