"""The sixel encoder: parse our own output (raster size, palette) and decode its pixels."""

import re

import numpy as np

from cloth_tui.tui.graphics import sixel
from cloth_tui.tui.graphics.layout import Layout
from cloth_tui.tui.graphics.palette import dither_cube_indices


def decode(data: str) -> tuple[tuple[int, int], dict[int, tuple[int, int, int]], np.ndarray]:
    """A small sixel decoder: ((width, height), palette in %, register index per pixel)."""
    assert data.startswith("\x1bP") and data.endswith("\x1b\\")
    body = data[data.index("q") + 1:-2]
    raster = re.match(r'"1;1;(\d+);(\d+)', body)
    w, h = int(raster.group(1)), int(raster.group(2))
    body = body[raster.end():]
    palette = {int(i): (int(r), int(g), int(b))
               for i, r, g, b in re.findall(r"#(\d+);2;(\d+);(\d+);(\d+)", body)}
    body = re.sub(r"#\d+;2;\d+;\d+;\d+", "", body)
    out = np.full((h + 6, w), -1, dtype=np.int64)
    band = x = colour = 0
    for token in re.findall(r"#\d+|!\d+[?-~]|[?-~]|\$|-", body):
        if token[0] == "#":
            colour = int(token[1:])
        elif token == "$":
            x = 0
        elif token == "-":
            band, x = band + 1, 0
        else:
            n, ch = (int(token[1:-1]), token[-1]) if token[0] == "!" else (1, token)
            bits = ord(ch) - 63
            for k in range(6):
                if bits >> k & 1:
                    out[6 * band + k, x:x + n] = colour
            x += n
    return (w, h), palette, out[:h]


def gradient(h: int, w: int) -> np.ndarray:
    y, x = np.mgrid[0:h, 0:w]
    return np.stack([x * 255 // max(w - 1, 1), y * 255 // max(h - 1, 1),
                     (x + y) * 127 // max(w + h, 1)], axis=-1).astype(np.uint8)


def test_sixel_decodes_to_the_dithered_indices_with_the_raster_size():
    image = gradient(23, 41)  # not a multiple of the 6-pixel bands
    (w, h), palette, pixels = decode(sixel.encode(image))
    assert (w, h) == (41, 23)
    assert len(palette) == len(sixel.PALETTE) == 216
    assert palette[0] == (0, 0, 0) and palette[215] == (100, 100, 100)
    assert np.array_equal(pixels, dither_cube_indices(image))  # every pixel, once


def test_long_runs_are_repeated_and_flat_colour_is_small():
    image = np.full((12, 300, 3), (95, 135, 175), dtype=np.uint8)  # a cube colour exactly
    data = sixel.encode(image)
    assert "!300" in data
    (_, _), _, pixels = decode(data)
    assert np.all(pixels == 16 * 0 + 36 * 1 + 6 * 2 + 3)  # cube index (1, 2, 3)
    assert len(data) < 4000  # palette definitions and two short bands


def test_runs_of_every_length_round_trip():
    rng = np.random.default_rng(3)
    runs = rng.integers(1, 40, 60)
    colours = np.repeat(rng.integers(0, 6, runs.size), runs)[:500]
    levels = np.array([0, 95, 135, 175, 215, 255], np.uint8)
    row = levels[colours]
    image = np.repeat(np.stack([row, row, row], -1)[None], 7, axis=0)
    (_, _), _, pixels = decode(sixel.encode(image))
    assert np.array_equal(pixels, dither_cube_indices(image))


def frames_in(stream: str) -> list[tuple[int, int, str]]:
    """(row, column, sixel sequence) of each sixel image in a stream, 1-based cells."""
    return [(int(r), int(c), d) for r, c, d in
            re.findall(r"\x1b\[(\d+);(\d+)H(\x1bP[^\x1b]*\x1b\\)", stream)]


def test_each_uncovered_rectangle_gets_its_part_of_one_dithered_picture():
    cell = (4, 6)
    # 10 × 5 cells at (2, 1); a notice over the bottom-right 6 × 2 cells
    layout = Layout((2, 1), 10, 5, ((0, 0, 10, 3), (0, 3, 4, 2)), cell, (40, 30))
    image = gradient(30, 40)
    frame = sixel.SixelFrames().prepare(image, layout)
    parts = frames_in(frame.draw)
    assert [(r, c) for r, c, _ in parts] == [(2, 3), (5, 3)]
    whole = dither_cube_indices(image)
    (w, h), _, top = decode(parts[0][2])
    assert (w, h) == (40, 18) and np.array_equal(top, whole[:18])
    (w, h), _, left = decode(parts[1][2])
    assert (w, h) == (16, 12) and np.array_equal(left, whole[18:, :16])  # the dither runs on


def test_a_frame_rendered_for_another_size_is_fitted_to_the_cells():
    layout = Layout((0, 0), 10, 5, ((0, 0, 10, 5),), (4, 6), (40, 30))
    stale = gradient(45, 60)  # rendered before the preview shrank
    (_, _, data), = frames_in(sixel.SixelFrames().prepare(stale, layout).draw)
    (w, h), _, _ = decode(data)
    assert (w, h) == (40, 30)  # never past the preview's cells


def test_a_frame_for_another_layout_is_not_shown_and_a_new_layout_erases_what_is_unfilled():
    cell = (4, 6)
    # the picture (sixel's size limit) fills 7 columns and 3 rows whole of 10 × 5
    layout = Layout((0, 0), 10, 5, ((0, 0, 10, 5),), cell, (30, 20), "48;5;189")
    frames = sixel.SixelFrames()
    frame = frames.prepare(gradient(20, 30), layout)
    moved = Layout((0, 0), 10, 5, ((0, 0, 6, 5),), cell, (30, 20), "48;5;189")
    assert frames.show(frame, moved) is None  # cut for the other layout: it would cover
    first = frames.show(frame, layout)
    erased = re.findall(r"\x1b\[(\d+);(\d+)H\x1b\[(\d+)X", first)
    # rows 1-3 from column 8 (the picture's partial column too); rows 4 and 5 whole
    assert erased == [("1", "8", "3"), ("2", "8", "3"), ("3", "8", "3"), ("4", "1", "10"),
                      ("5", "1", "10")]
    assert first.index("\x1b[0;48;5;189m") < first.index("X") < first.index("\x1bP")
    again = frames.show(frames.prepare(gradient(20, 30), layout), layout)
    assert "X" not in again.split("\x1bP")[0]  # same layout: nothing stale to erase
