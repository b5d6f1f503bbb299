"""Fixed palettes and ordered dithering, shared by sixel and by half-blocks below truecolor.

Why ordered (Bayer) dithering rather than error diffusion: it is a per-pixel NumPy expression
(no serial loop), and its pattern stays put from one frame to the next, so a moving cloth
does not shimmer. Nearest-colour search goes through a 32³ lookup table made once per
palette, so a frame costs three shifts and one fancy index.
"""

from __future__ import annotations

from functools import lru_cache

import numpy as np

CUBE_LEVELS = (0, 95, 135, 175, 215, 255)  # xterm's 6×6×6 colour cube (indices 16–231)
GREY_LEVELS = tuple(8 + 10 * k for k in range(24))  # xterm's grey ramp (indices 232–255)
_LUT_BITS = 5  # 32 levels a channel: finer than the cube's steps, 32 kB a table

# The 4×4 Bayer matrix, as thresholds in (-0.5, 0.5).
_BAYER4 = np.array([[0, 8, 2, 10], [12, 4, 14, 6], [3, 11, 1, 9], [15, 7, 13, 5]],
                   dtype=np.float32)
BAYER4 = (_BAYER4 + 0.5) / 16.0 - 0.5


def xterm_256() -> np.ndarray:
    """(256, 3) uint8: the xterm palette; 0–15 are the common VGA-like system colours."""
    system = [(0, 0, 0), (128, 0, 0), (0, 128, 0), (128, 128, 0), (0, 0, 128), (128, 0, 128),
              (0, 128, 128), (192, 192, 192), (128, 128, 128), (255, 0, 0), (0, 255, 0),
              (255, 255, 0), (0, 0, 255), (255, 0, 255), (0, 255, 255), (255, 255, 255)]
    cube = [(r, g, b) for r in CUBE_LEVELS for g in CUBE_LEVELS for b in CUBE_LEVELS]
    greys = [(v, v, v) for v in GREY_LEVELS]
    return np.array(system + cube + greys, dtype=np.uint8)


@lru_cache(maxsize=8)
def _nearest_table(palette_bytes: bytes) -> np.ndarray:
    palette = np.frombuffer(palette_bytes, dtype=np.uint8).reshape(-1, 3).astype(np.float32)
    step = 1 << (8 - _LUT_BITS)
    centres = np.arange(1 << _LUT_BITS, dtype=np.float32) * step + (step - 1) / 2
    grid = np.stack(np.meshgrid(centres, centres, centres, indexing="ij"), axis=-1)
    # Perceptual-ish weights (green counts most), as Rich's and most quantisers' do.
    weights = np.array([0.30, 0.59, 0.11], dtype=np.float32)
    d = (((grid.reshape(-1, 1, 3) - palette[None]) ** 2) * weights).sum(axis=-1)
    return d.argmin(axis=1).astype(np.uint8 if len(palette) <= 256 else np.uint16
                                   ).reshape((1 << _LUT_BITS,) * 3)


def palette_spread(palette: np.ndarray) -> float:
    """How far apart neighbouring palette colours are, a channel (the dither's amplitude):
    the mean nearest-neighbour distance between entries, per channel."""
    p = palette.astype(np.float32)
    d = np.sqrt(((p[:, None] - p[None]) ** 2).sum(-1))
    np.fill_diagonal(d, np.inf)
    return float(np.median(d.min(axis=1)) / np.sqrt(3.0))


def dither_indices(image: np.ndarray, palette: np.ndarray, amplitude: float | None = None
                   ) -> np.ndarray:
    """Palette index of each pixel of an (H, W, 3) uint8 image, with a 4×4 ordered dither of
    `amplitude` (default: the palette's spacing) so that gradients become patterns of the
    two nearest colours instead of flat bands."""
    h, w = image.shape[:2]
    if amplitude is None:
        amplitude = palette_spread(palette)
    table = _nearest_table(np.ascontiguousarray(palette, dtype=np.uint8).tobytes())
    threshold = np.tile(BAYER4, ((h + 3) // 4, (w + 3) // 4))[:h, :w, None]
    shifted = image[..., :3].astype(np.float32) + threshold * amplitude
    q = np.clip(shifted, 0, 255).astype(np.uint8) >> (8 - _LUT_BITS)
    return table[q[..., 0], q[..., 1], q[..., 2]]


def cube() -> np.ndarray:
    """(216, 3): the 6×6×6 cube alone, index 36·r + 6·g + b."""
    return xterm_256()[16:232]


@lru_cache(maxsize=1)
def _cube_tables() -> tuple[np.ndarray, np.ndarray, np.ndarray]:
    """For each of the 16 Bayer thresholds and each channel value, the cube level it
    dithers to, premultiplied by 36, 6 and 1 for the red, green and blue parts of the index."""
    levels = np.array(CUBE_LEVELS, dtype=np.float64)
    v = np.arange(256, dtype=np.float64)
    low = np.clip(np.searchsorted(levels, v, side="right") - 1, 0, len(levels) - 2)
    frac = (v - levels[low]) / (levels[low + 1] - levels[low])
    thresholds = (BAYER4.ravel().astype(np.float64) + 0.5)[:, None]
    level = (low[None, :] + (frac[None, :] > thresholds)).astype(np.uint8)  # (16, 256)
    return 36 * level, 6 * level, level


def dither_cube_indices(image: np.ndarray) -> np.ndarray:
    """Index into `cube()` of each pixel, dithered per channel between the two cube levels
    around its value (the cube's steps are uneven: 0→95 is the widest), so that each 4×4
    patch keeps the input's mean channel by channel. Table look-ups only."""
    h, w = image.shape[:2]
    red, green, blue = _cube_tables()
    cell = (np.arange(h)[:, None] % 4) * 4 + np.arange(w)[None, :] % 4  # Bayer entry
    return (red[cell, image[..., 0]] + green[cell, image[..., 1]] + blue[cell, image[..., 2]])


def dither_rgb(image: np.ndarray, palette: np.ndarray) -> np.ndarray:
    """The image dithered to the palette's own colours, (H, W, 3) uint8; the cube gets its
    own per-channel dither."""
    if palette.shape == (216, 3) and np.array_equal(palette, cube()):
        return palette[dither_cube_indices(image)]
    return palette[dither_indices(image, palette)]


def rich_standard() -> np.ndarray:
    """(16, 3): the colours Rich takes the 16 system colours to be. Dithering to exactly
    these makes Rich's nearest-colour downgrade keep each pixel's choice."""
    from ..textual_adapter import rich_standard_palette
    return np.array(rich_standard_palette(), dtype=np.uint8)


def palette_for(colors: str) -> np.ndarray | None:
    """The palette to dither half-blocks to for a colour depth ('truecolor', '256', '16'):
    None for truecolor (nothing to do)."""
    # 256: the cube (Rich's downgrade sends 4 near-grey cube colours to the nearest grey of
    # the ramp instead, a close colour).
    return {"256": cube, "16": rich_standard}.get(colors, lambda: None)()
