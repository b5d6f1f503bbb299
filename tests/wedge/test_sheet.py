"""The contact sheet: each run's picture in its place, labels around, unfinished runs grey."""

import numpy as np

from cloth_tui.scene_files import load
from cloth_tui.wedge.engine import Failed
from cloth_tui.wedge.plan import plan
from cloth_tui.wedge.sheet import EMPTY, VIDEO_BLOCK, clip_frames, layout_sheet, still

THUMB = (48, 32)


def result(colour, frames=None):
    img = np.full((THUMB[1], THUMB[0], 3), colour, np.uint8)
    return {"image": img, "clip": None if frames is None else np.stack([img] * frames),
            "max_stretch": 0.01, "energy_drift": -0.1, "wall_s": 0.5, "halted": None}


def test_pictures_land_in_their_cells_and_unfinished_ones_are_grey():
    varies, cells = plan(load("default"), ["forces.wind_strength=2,8", "scene.friction=0,1"])
    results = [result((255, 0, 0)), Failed("RuntimeError: boom"), result((0, 0, 255)), None]
    sheet = layout_sheet(varies, cells, results, THUMB, "title")
    img = still(sheet, results)
    assert len(sheet.boxes) == 4 and len(set(sheet.boxes)) == 4
    for (x, y), r in zip(sheet.boxes, results):
        patch = img[y:y + THUMB[1], x:x + THUMB[0]].reshape(-1, 3)
        want = r["image"][0, 0] if isinstance(r, dict) else EMPTY
        assert (patch == want).all()
    # the labels are drawn: left of and above the grid is not plain background
    x0 = min(x for x, _ in sheet.boxes)
    y0 = min(y for _, y in sheet.boxes)
    assert (img[y0:, :x0] != img[-1, -1]).any() and (img[:y0, x0:] != img[-1, -1]).any()


def test_clip_sheet_sides_are_multiples_of_16_and_frames_follow_the_clips():
    varies, cells = plan(load("default"), ["scene.friction=0,1"])
    results = [result((10, 200, 10), frames=3), None]
    sheet = layout_sheet(varies, cells, results, THUMB, "title", VIDEO_BLOCK)
    frames = list(clip_frames(sheet, results, 3))
    assert len(frames) == 3
    h, w = frames[0].shape[:2]
    assert h % 16 == 0 and w % 16 == 0
    x, y = sheet.boxes[0]
    assert (frames[2][y, x] == (10, 200, 10)).all()
