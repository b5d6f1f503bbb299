"""A NumPy sixel encoder: an RGB frame → one DCS string (`ESC P q … ESC \\`).

Palette: the fixed 6×6×6 colour cube (216 registers, below xterm's and VT340 emulations'
256, the same for every frame, so nothing is chosen per frame), with a 4×4 ordered dither per
channel so the cloth's shading reads as a gradient and not as bands.

Layout (the DEC spec): bands six pixels high; in a band each colour in use is one row of
characters `63 + bits` (bit k = pixel row k of the band), `$` returns to the band's start for
the next colour, `-` goes to the next band, `!n c` repeats c n times. The run-length pass is
vectorised over every colour row of the image at once; Python only joins the rows.

`SixelFrames` puts frames on the screen: sixel has no ids and no placements, so a frame is
drawn over the last, one sixel image per uncovered rectangle of the preview (layout.py), cut
from one dithered picture so the dither pattern runs on across the cuts. Writing a cell
erases xterm's sixel pixels in it, so the app's own widgets over the preview take the picture
off their cells when they are drawn; what is left to do is not to draw over them again, and to
erase the cells a smaller picture no longer reaches when the layout changes.
"""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np

from .layout import Layout, goto, pixel_box
from .palette import cube, dither_cube_indices, dither_indices

DCS = "\x1bP"
ST = "\x1b\\"
BAND = 6
_BIT = np.array([1, 2, 4, 8, 16, 32], dtype=np.int64)
PALETTE = cube()


def palette_definitions(palette: np.ndarray) -> str:
    """`#i;2;r;g;b` for each register, channels in percent as sixel wants them."""
    pct = np.rint(palette.astype(np.float32) * (100 / 255)).astype(int)
    return "".join(f"#{i};2;{r};{g};{b}" for i, (r, g, b) in enumerate(pct.tolist()))


def _colour_rows(indices: np.ndarray) -> tuple[np.ndarray, list[tuple[int, int]]]:
    """Sixel bit rows: (R, W) uint8 in 0..63, one row per (band, colour used in it), and the
    (band, colour) of each row, bands in order. One pass over the whole image: a table of
    which colours each band uses numbers the rows, and one bincount sums each pixel's bit
    into its row (a band row has one colour per pixel, so the sum is the OR)."""
    h, w = indices.shape
    bands = (h + BAND - 1) // BAND
    y = np.arange(h)
    band_of = np.repeat(y // BAND, w).reshape(h, w)
    colour = indices.astype(np.intp)
    used = np.zeros((bands, 256), dtype=bool)
    used[band_of, colour] = True
    row_of = np.cumsum(used.ravel()).reshape(bands, 256) - 1
    n_rows = int(used.sum())
    slot = row_of[band_of, colour] * w + np.arange(w)
    bit = np.broadcast_to(_BIT[y % BAND][:, None], (h, w))
    rows = np.bincount(slot.ravel(), weights=bit.ravel(), minlength=n_rows * w)
    band_idx, colour_idx = np.nonzero(used)
    return rows.reshape(n_rows, w).astype(np.uint8), list(zip(band_idx.tolist(),
                                                              colour_idx.tolist()))


def _run_length(rows: np.ndarray) -> list[bytes]:
    """Each row of sixel values as sixel characters with `!n` for runs longer than 3."""
    n, w = rows.shape
    flat = rows.ravel()
    starts = np.ones(flat.size, dtype=bool)
    starts[1:] = flat[1:] != flat[:-1]
    starts[::w] = True  # a run never crosses rows
    begin = np.flatnonzero(starts).astype(np.int32)
    length = np.diff(np.append(begin, np.int32(flat.size)))
    char = flat[begin] + 63
    digits = 1 + (length >= 10).astype(np.int32) + (length >= 100) + (length >= 1000)
    long_run = length > 3
    size = np.where(long_run, digits + 2, length)  # "!" digits char  |  char × length
    end = np.cumsum(size)
    offset = end - size
    out = np.empty(int(end[-1]) if end.size else 0, dtype=np.uint8)
    short = ~long_run
    if short.any():
        reps = length[short]
        pos = np.repeat(offset[short], reps) + (np.arange(reps.sum()) -
                                                np.repeat(np.cumsum(reps) - reps, reps))
        out[pos] = np.repeat(char[short], reps)
    if long_run.any():
        o, ln, dg, ch = offset[long_run], length[long_run], digits[long_run], char[long_run]
        out[o] = ord("!")
        for k in range(int(dg.max())):
            has = dg > k
            out[o[has] + 1 + k] = ord("0") + (ln[has] // 10 ** (dg[has] - 1 - k)) % 10
        out[o + 1 + dg] = ch
    row_end = np.searchsorted(begin, np.arange(1, n + 1) * w)  # runs per row, cumulative
    bounds = np.concatenate(([0], end[row_end - 1]))
    data = out.tobytes()
    return [data[bounds[i]:bounds[i + 1]] for i in range(n)]


def encode(image: np.ndarray, palette: np.ndarray = PALETTE) -> str:
    """The (H, W, 3) uint8 image as a complete sixel sequence, drawn at the cursor."""
    indices = (dither_cube_indices(image) if palette is PALETTE
               else dither_indices(image, palette))
    return encode_indices(indices, palette)


def encode_indices(indices: np.ndarray, palette: np.ndarray = PALETTE) -> str:
    """An (H, W) image of palette indices as a complete sixel sequence."""
    h, w = indices.shape
    rows, keys = _colour_rows(indices)
    encoded = _run_length(rows)
    parts = [f'{DCS}0;1;0q"1;1;{w};{h}', palette_definitions(palette)]
    band_parts: list[bytes] = []
    current = 0
    for (band, colour), data in zip(keys, encoded):
        if band != current:
            band_parts[-1] = band_parts[-1][:-1] + b"-"  # last "$" of a band → next band
            current = band
        band_parts.append(b"#%d%s$" % (colour, data))
    parts.append(b"".join(band_parts).decode("ascii"))
    parts.append(ST)
    return "".join(parts)


def fit(image: np.ndarray, width: int, height: int) -> np.ndarray:
    """The image resampled (nearest pixel) to width × height: sixel is shown unscaled, so a
    frame rendered for another size would reach past the preview's cells."""
    h, w = image.shape[:2]
    if (w, h) == (width, height):
        return image
    ys = ((np.arange(height) + 0.5) * (h / height)).astype(np.intp)
    xs = ((np.arange(width) + 0.5) * (w / width)).astype(np.intp)
    return image[ys[:, None], xs[None, :], :3]


def erase_unfilled(layout: Layout) -> str:
    """Erase (ECH, in the preview's own background) every cell of the layout's rectangles
    that the picture does not fill whole: a larger picture's pixels would stay there."""
    pw, ph = layout.picture_px
    cw, ch = layout.cell_px
    full_cols, full_rows = pw // cw, ph // ch
    out = []
    for x, y, w, h in layout.rects:
        for row in range(y, y + h):
            start = x if row >= full_rows else max(x, full_cols)
            if start < x + w:
                out.append(f"{goto(layout, (start, row, 0, 0))}\x1b[{x + w - start}X")
    if not out:
        return ""
    return f"\x1b[0;{layout.fill_sgr}m" + "".join(out) + "\x1b[0m"


@dataclass(frozen=True)
class SixelFrame:
    layout: Layout  # what it was cut for
    erase: str      # erase_unfilled(layout)
    draw: str       # a sixel image at each rectangle's top-left cell


class SixelFrames:
    """`prepare` runs on the encoding thread and touches no state; `show`, `relayout` and
    `clear` run on the UI thread in the order their output is written."""

    def __init__(self) -> None:
        self._shown: Layout | None = None  # the layout of the picture on screen

    def prepare(self, image: np.ndarray, layout: Layout) -> SixelFrame:
        pw, ph = layout.picture_px
        indices = dither_cube_indices(fit(image, pw, ph))
        parts = []
        for rect in layout.rects:
            x0, y0, x1, y1 = pixel_box(rect, layout.cell_px)
            x1, y1 = min(x1, pw), min(y1, ph)
            if x1 > x0 and y1 > y0:
                parts.append(goto(layout, rect) + encode_indices(indices[y0:y1, x0:x1]))
        return SixelFrame(layout, erase_unfilled(layout), "".join(parts))

    def show(self, frame: SixelFrame, layout: Layout) -> str | None:
        """The frame's bytes, or None if it was cut for another layout (it would be drawn
        over whatever now covers the preview)."""
        if frame.layout != layout:
            return None
        erase = frame.erase if layout != self._shown else ""
        self._shown = layout
        return erase + frame.draw

    def relayout(self, layout: Layout) -> str:
        return ""  # the covering widgets' own drawing erased the picture under them

    def clear(self) -> str:
        self._shown = None
        return ""  # the cells' next repaint covers it
