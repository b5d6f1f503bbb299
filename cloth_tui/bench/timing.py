"""Timing discipline shared by every benchmark: warm up, then time several blocks and report
the median with its spread. Numbers from here are printed, never asserted by tests."""

from __future__ import annotations

import statistics
import time
from dataclasses import dataclass
from typing import Callable


@dataclass(frozen=True)
class Timing:
    median_s: float   # per call
    min_s: float
    max_s: float
    blocks: int
    calls_per_block: int

    @property
    def spread(self) -> float:
        """(max − min) / median over the blocks."""
        return (self.max_s - self.min_s) / self.median_s if self.median_s else 0.0

    def as_dict(self) -> dict:
        return {"median_s": self.median_s, "min_s": self.min_s, "max_s": self.max_s,
                "spread": self.spread, "blocks": self.blocks,
                "calls_per_block": self.calls_per_block}


def time_calls(fn: Callable[[], None], *, block_s: float = 0.2, blocks: int = 5,
               warmup: int = 2) -> Timing:
    """Per-call time of `fn`: `warmup` untimed calls, then `blocks` blocks of about `block_s`."""
    for _ in range(warmup):
        fn()
    t0 = time.perf_counter()
    fn()
    one = max(time.perf_counter() - t0, 1e-7)
    calls = max(1, int(block_s / one))
    per_call = []
    for _ in range(blocks):
        t0 = time.perf_counter()
        for _ in range(calls):
            fn()
        per_call.append((time.perf_counter() - t0) / calls)
    return Timing(statistics.median(per_call), min(per_call), max(per_call), blocks, calls)


def first_call_s(fn: Callable[[], None]) -> float:
    """Time of one call; on a fresh process this is the JIT compile or cache load."""
    t0 = time.perf_counter()
    fn()
    return time.perf_counter() - t0


def time_alternating(fns: dict[str, Callable[[], None]], *, block_s: float = 0.1,
                     blocks: int = 5, warmup: int = 2,
                     clock: Callable[[], float] = time.perf_counter) -> dict[str, Timing]:
    """Per-call time of each of `fns`, their blocks taken in turn (A, B, C, A, B, C, …) so
    that a change in the machine's load hits all alike. `clock` = time.thread_time measures
    the CPU time of this thread instead of wall time: for one-thread comparisons on a
    machine that others share."""
    calls, times = {}, {name: [] for name in fns}
    for name, fn in fns.items():
        for _ in range(warmup):
            fn()
        t0 = clock()
        fn()
        calls[name] = max(1, int(block_s / max(clock() - t0, 1e-7)))
    for _ in range(blocks):
        for name, fn in fns.items():
            t0 = clock()
            for _ in range(calls[name]):
                fn()
            times[name].append((clock() - t0) / calls[name])
    return {name: Timing(statistics.median(t), min(t), max(t), blocks, calls[name])
            for name, t in times.items()}
