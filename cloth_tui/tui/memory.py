"""What keeps the app's memory bounded while it runs for hours (see docs/app.md, Memory).

1. Textual's `Strip.divide` caches its result on the strip. When the only cut is the
   strip's own width the result is `[self]`, so the strip then refers to itself through its
   cache. The compositor divides every line it redraws, so every redrawn line became a
   reference cycle that only the cycle collector frees: for the preview ~2,400 lines
   (~51,000 Segments) a second, 3.6 MB/s while the collector was tuned to run rarely
   (Textual 8.2.8). `install_acyclic_strip_divide()` wraps `divide` so that case returns a
   fresh `[self]` without caching it: the same result, no cycle. Every other case is
   Textual's own code, cache included (its cached pieces are new strips, which do not
   refer back).
2. `freeze_start_up_objects()`, once start-up is over, moves what it built (Textual's ~300
   widgets; numba, VTK and PyVista, imported by the other threads) out of the collector's
   reach, so a full collection scans only what was made since. The thresholds stay
   Python's defaults. Measured in the running app: a full collection about once a second,
   ~10 ms of CPU (median; 17 ms wall on a loaded machine), against ~120 ms when frozen
   before the renderer's imports.
"""

from __future__ import annotations

import gc
from typing import Iterable, Sequence

from textual.strip import Strip

_textual_divide = Strip.divide


def _divide_without_self_cycle(self: Strip, cuts: Iterable[int]) -> Sequence[Strip]:
    cell_length = self.cell_length
    cuts = [cut for cut in cuts if cut <= cell_length]  # as Textual filters them
    if cuts == [cell_length]:
        return [self]
    return _textual_divide(self, cuts)


def install_acyclic_strip_divide() -> None:
    """Idempotent; process-wide (Strip is Textual's class)."""
    Strip.divide = _divide_without_self_cycle  # type: ignore[method-assign]


def freeze_start_up_objects() -> None:
    """Collect once, then exclude every object alive now from later collections."""
    gc.collect()
    gc.freeze()
