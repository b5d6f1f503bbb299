"""Where a true-pixel picture may be drawn: the preview's cells minus whatever covers them.

Kitty and sixel pictures are drawn over text, so a drawer, a notice or a tooltip over the
preview would be hidden under the picture (kitty) or painted over by the next frame (sixel).
The picture is therefore cut into rectangles of uncovered cells, and each rectangle shows its
own part of the frame: around a notice at the bottom right, the rows beside it keep their
picture instead of the whole width stopping above it.
"""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np

Rect = tuple[int, int, int, int]  # (x, y, width, height) in cells


@dataclass(frozen=True)
class Layout:
    """The preview's place on the screen and the parts of it the picture may cover."""
    origin: tuple[int, int]       # screen cell of the preview's top-left (x, y), 0-based
    cols: int                     # the preview's size in cells: the whole frame maps onto it
    rows: int
    rects: tuple[Rect, ...]       # uncovered parts, relative to origin
    cell_px: tuple[int, int] = (10, 20)  # (width, height) of a cell in pixels
    picture_px: tuple[int, int] = (0, 0)  # the whole frame's pixels as sixel shows it
    fill_sgr: str = ""            # SGR parameters of the preview's own blank cells


def uncovered_rects(cols: int, rows: int, covers: list[Rect]) -> tuple[Rect, ...]:
    """The cells of a cols × rows area not in any of `covers` (relative rectangles, clipped
    here), as few rectangles: each row's free runs, with consecutive rows of the same runs
    merged into one rectangle."""
    if cols <= 0 or rows <= 0:
        return ()
    covered = np.zeros((rows, cols), dtype=bool)
    for x, y, w, h in covers:
        covered[max(y, 0):max(y + h, 0), max(x, 0):max(x + w, 0)] = True
    free = np.zeros((rows, cols + 2), dtype=np.int8)
    free[:, 1:-1] = ~covered
    edges = np.diff(free, axis=1)  # +1 where a free run starts, -1 after it ends
    rects: list[Rect] = []
    open_runs: dict[tuple[int, int], int] = {}  # (x, width) → first row of its rectangle
    for y in range(rows + 1):
        if y < rows:
            starts = np.flatnonzero(edges[y] == 1)
            ends = np.flatnonzero(edges[y] == -1)
            runs = set(zip(starts.tolist(), (ends - starts).tolist()))
        else:
            runs = set()
        for run in [r for r in open_runs if r not in runs]:
            top = open_runs.pop(run)
            rects.append((run[0], top, run[1], y - top))
        for run in runs:
            open_runs.setdefault(run, y)
    return tuple(sorted(rects, key=lambda r: (r[1], r[0])))


def goto(layout: Layout, rect: Rect) -> str:
    """Move the cursor to a rectangle's top-left cell (CUP is 1-based)."""
    return f"\x1b[{layout.origin[1] + rect[1] + 1};{layout.origin[0] + rect[0] + 1}H"


def pixel_box(rect: Rect, cell_px: tuple[int, int]) -> tuple[int, int, int, int]:
    """(x0, y0, x1, y1) in pixels of a rectangle of cells, for a picture of exactly the cells'
    pixel size."""
    x, y, w, h = rect
    cw, ch = cell_px
    return x * cw, y * ch, (x + w) * cw, (y + h) * ch
