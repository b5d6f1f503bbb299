"""Ordered dithering to a terminal's palette, and that Rich keeps the colours chosen."""

import numpy as np
from rich.color import Color, ColorSystem

from cloth_tui.tui.graphics.palette import cube, dither_indices, dither_rgb, palette_for


def ramp(w=64, h=8):
    v = np.linspace(40, 220, w).astype(np.uint8)
    return np.repeat(np.stack([v, v // 2, v // 3], -1)[None], h, axis=0)


def test_dithering_mixes_neighbours_so_the_mean_follows_a_gradient():
    image = ramp()
    palette = cube()
    out = dither_rgb(image, palette).astype(float)
    nearest = palette[dither_indices(image, palette, amplitude=0.0)].astype(float)
    # The 4×4 cells' mean follows the input much better than the nearest colour does.
    blocks = lambda a: a.reshape(2, 4, 16, 4, 3).mean(axis=(1, 3))  # noqa: E731
    err_dither = np.abs(blocks(out) - blocks(image.astype(float))).mean()
    err_nearest = np.abs(blocks(nearest) - blocks(image.astype(float))).mean()
    assert err_dither < 0.6 * err_nearest
    assert len({tuple(c) for c in out.reshape(-1, 3)}) > len({tuple(c) for c in
                                                            nearest.reshape(-1, 3)})


def test_rich_downgrade_keeps_each_dithered_colour():
    image = np.random.default_rng(0).integers(0, 256, (16, 16, 3), dtype=np.uint8)
    # 16 colours: each pixel's colour is one Rich's downgrade keeps as the same entry.
    palette = palette_for("16")
    out = dither_rgb(image, palette)
    index = {tuple(map(int, c)): i for i, c in enumerate(palette)}
    for c in {tuple(map(int, c)) for c in out.reshape(-1, 3)}:
        assert Color.from_rgb(*c).downgrade(ColorSystem.STANDARD).number == index[c]
    # 256: cube colours go to their own cube entry but 4 near-greys, sent to the ramp.
    kept = sum(Color.from_rgb(*map(int, c)).downgrade(ColorSystem.EIGHT_BIT).number == 16 + i
               for i, c in enumerate(palette_for("256")))
    assert kept == 216 - 4
    assert palette_for("truecolor") is None
