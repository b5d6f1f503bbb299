"""What keeps the app's memory bounded while it runs for hours (see docs/app.md, Memory).

1. Textual's `Strip.divide` caches its result on the strip. When the only cut is the
   strip's own width the result is `[self]`, so the strip then refers to itself through its
   cache. The compositor divides every line it redraws, so every redrawn line would be a
   reference cycle that only the cycle collector frees (the preview redraws thousands of
   lines a second). `install_acyclic_strip_divide()` wraps `divide` so that case returns a
   fresh `[self]` without caching it: the same result, no cycle. Every other case is
   Textual's own code, cache included (its cached pieces are new strips, which do not
   refer back).
2. `freeze_start_up_objects()`, once start-up is over, moves what it built (Textual's ~300
   widgets; numba, VTK and PyVista, imported by the other threads) out of the collector's
   reach, so a full collection scans only what was made since. The thresholds stay
   Python's defaults. What a collection then costs is measured in docs/app.md, Memory.
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
