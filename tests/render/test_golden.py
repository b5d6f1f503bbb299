"""Golden images: small renders compared with stored baselines, with a tolerance that
absorbs tiny GL differences (driver versions, rounding) but not a changed look.

Regenerate the baselines after an intended change of look, then look at them:
    CLOTH_TUI_UPDATE_GOLDEN=1 pytest tests/render/test_golden.py
"""

import os
from pathlib import Path

import numpy as np
import pytest

from cloth_tui.sim.colliders import ObjectPose

from .helpers import draped, scene_with

SNAPSHOTS = Path(__file__).parent / "__snapshots__"
UPDATE = os.environ.get("CLOTH_TUI_UPDATE_GOLDEN") == "1"
SIZE = (160, 120)
MAX_MEAN_DIFF = 2.0       # mean |difference| over all channels, 0..255
MAX_BAD_SHARE = 0.01      # share of pixels allowed to differ by more than BAD_PIXEL
BAD_PIXEL = 48

OBJECTS = (ObjectPose("sphere", (-0.3, -0.3, 0.2), radius=0.2),
           ObjectPose("box", (0.3, -0.4, -0.2), size=(0.3, 0.2, 0.3)),
           ObjectPose("capsule", (0.3, -0.3, 0.35), radius=0.08, axis=(1.0, 0.0, 0.0),
                      length=0.3),
           ObjectPose("plane", (0.0, -0.45, -0.5), normal=(0.0, 0.3, 1.0)))

CASES = {
    "default": lambda: draped(scene_with()),
    "solid_textured": lambda: draped(scene_with(wireframe=False, cloth_texture="maze",
                                                ground_texture="grass")),
    "constraints_objects": lambda: draped(scene_with(show_constraints=True, wireframe=False,
                                                     cloth_color="#3060c0"),
                                          sag=0.1, objects=OBJECTS),
}


def _compare(image: np.ndarray, baseline: np.ndarray) -> tuple[float, float]:
    diff = np.abs(image.astype(np.int16) - baseline.astype(np.int16))
    return float(diff.mean()), float((diff.max(axis=2) > BAD_PIXEL).mean())


@pytest.mark.parametrize("name", sorted(CASES))
def test_golden(renderer, name):
    import imageio.v3 as iio

    snap = CASES[name]()
    renderer.resize(*SIZE)
    renderer.update_scene(snap.scene)
    renderer.reset_camera()
    image = renderer.render(snap)
    path = SNAPSHOTS / f"{name}.png"
    if UPDATE or not path.exists():
        SNAPSHOTS.mkdir(exist_ok=True)
        iio.imwrite(path, image)
        if not UPDATE:
            pytest.skip(f"baseline {path.name} created; rerun to compare")
        return
    baseline = iio.imread(path)
    assert baseline.shape == image.shape
    mean, bad = _compare(image, baseline)
    if mean > MAX_MEAN_DIFF or bad > MAX_BAD_SHARE:
        iio.imwrite(SNAPSHOTS / f"{name}.actual.png", image)  # to look at; not committed
    assert mean <= MAX_MEAN_DIFF, f"{name}: mean difference {mean:.2f} (see {name}.actual.png)"
    assert bad <= MAX_BAD_SHARE, f"{name}: {bad:.1%} of pixels differ (see {name}.actual.png)"
