"""Golden images: small renders compared with stored baselines, with a tolerance that
absorbs tiny GL differences (driver versions, rounding) but not a changed look.

Regenerate the baselines after an intended change of look, then look at them:
    CLOTH_TUI_UPDATE_GOLDEN=1 pytest tests/render/test_golden.py
"""

import os
from pathlib import Path

import numpy as np
import pytest

from cloth_tui.sim.protocols import ObjectPose
from cloth_tui.sim.collision.shapes.base import unit

from .helpers import draped, scene_with

SNAPSHOTS = Path(__file__).parent / "__snapshots__"
UPDATE = os.environ.get("CLOTH_TUI_UPDATE_GOLDEN") == "1"
SIZE = (160, 120)
MAX_MEAN_DIFF = 2.0       # mean |difference| over all channels, 0..255
MAX_BAD_SHARE = 0.01      # share of pixels allowed to differ by more than BAD_PIXEL
BAD_PIXEL = 48

OBJECTS = (ObjectPose("sphere", {"radius": 0.2}, (-0.3, -0.3, 0.2)),
           ObjectPose("box", {"size": (0.3, 0.2, 0.3)}, (0.3, -0.4, -0.2)),
           ObjectPose("capsule", {"radius": 0.08, "axis": (1.0, 0.0, 0.0), "length": 0.3},
                      (0.3, -0.3, 0.35)),
           ObjectPose("plane", {"normal": unit((0.0, 0.3, 1.0))}, (0.0, -0.45, -0.5)))

CASES = {
    "default": lambda: draped(scene_with()),
    "solid_textured": lambda: draped(scene_with(wireframe=False, cloth_texture="maze",
                                                ground_texture="grass")),
    "constraints_objects": lambda: draped(scene_with(show_constraints=True, wireframe=False,
                                                     cloth_color="#3060c0"),
                                          sag=0.1, objects=OBJECTS),
    # a 3:1 sheet, 1.5 m × 0.5 m at 31 × 11 particles: its poles at the rectangle's
    # corners, the maze's square cells square on it (not stretched 3:1), its shadow a strip
    "banner_3to1": lambda: draped(scene_with(wireframe=False, cloth_texture="maze").with_values(
        {"cloth.size": [1.5, 0.5], "cloth.resolution": 31}), sag=0.1),
}


def _compare(image: np.ndarray, baseline: np.ndarray) -> tuple[float, float]:
    diff = np.abs(image.astype(np.int16) - baseline.astype(np.int16))
    return float(diff.mean()), float((diff.max(axis=2) > BAD_PIXEL).mean())


def check_against_baseline(image: np.ndarray, path: Path, update: bool = False) -> None:
    """Compare with the baseline at `path` (or rewrite it when updating). A missing baseline
    fails: a skipped comparison would let a lost or never-committed file pass unnoticed."""
    import imageio.v3 as iio

    if update:
        path.parent.mkdir(exist_ok=True)
        iio.imwrite(path, image)
        return
    if not path.exists():
        pytest.fail(f"baseline {path.name} is missing; create it with "
                    f"CLOTH_TUI_UPDATE_GOLDEN=1, look at it and commit it")
    baseline = iio.imread(path)
    assert baseline.shape == image.shape
    mean, bad = _compare(image, baseline)
    name = path.stem
    actual = path.with_name(f"{name}.actual.png")
    if mean > MAX_MEAN_DIFF or bad > MAX_BAD_SHARE:
        iio.imwrite(actual, image)  # to look at; not committed
    assert mean <= MAX_MEAN_DIFF, f"{name}: mean difference {mean:.2f} (see {actual.name})"
    assert bad <= MAX_BAD_SHARE, f"{name}: {bad:.1%} of pixels differ (see {actual.name})"


@pytest.mark.parametrize("name", sorted(CASES))
def test_golden(renderer, name):
    snap = CASES[name]()
    renderer.resize(*SIZE)
    renderer.update_scene(snap.scene)
    renderer.reset_camera()
    check_against_baseline(renderer.render(snap), SNAPSHOTS / f"{name}.png", UPDATE)


def test_a_missing_baseline_fails_and_writes_nothing(tmp_path):
    image = np.zeros((*SIZE[::-1], 3), np.uint8)
    with pytest.raises(BaseException) as outcome:  # broad: a skip must not pass as a skip
        check_against_baseline(image, tmp_path / "lost.png")
    assert outcome.type is pytest.fail.Exception and "missing" in str(outcome.value)
    assert not any(tmp_path.iterdir())


def test_a_changed_image_fails_and_a_same_one_passes(tmp_path):
    image = np.full((*SIZE[::-1], 3), 100, np.uint8)
    check_against_baseline(image, tmp_path / "look.png", update=True)
    check_against_baseline(image, tmp_path / "look.png")
    with pytest.raises(AssertionError, match="mean difference"):
        check_against_baseline(image // 2, tmp_path / "look.png")
