"""The bake player's playhead on a given clock: real-time playback, wrap, steps, seeks."""

import numpy as np
import pytest

from cloth_tui.cli import main

pytest.importorskip("pxr")

from cloth_tui.io.bake_player import BakePlayer  # noqa: E402
from cloth_tui.io.usd_read import UsdBake  # noqa: E402

FRAMES = 10


@pytest.fixture(scope="module")
def bake(tmp_path_factory):
    out = tmp_path_factory.mktemp("bake") / "p.usda"
    assert main(["bake", "sphere", "-o", str(out), "--frames", str(FRAMES),
                 "--set", "cloth.resolution=5", "--set", "behavior.frame_rate=20"]) == 0
    return UsdBake(out)


def test_playing_follows_the_clock_at_the_bakes_rate_and_wraps(bake):
    p = BakePlayer(bake, bake.scene)
    assert (p.index, p.frame, p.frame_rate) == (0, 1, 20.0)
    p.play(now=100.0)
    assert not p.advance(100.04)          # under one frame's time (50 ms)
    assert p.advance(100.051) and p.index == 1
    assert p.advance(100.26) and p.index == 5   # a late caller skips, the speed stays
    assert p.time == pytest.approx(6 / 20)
    p.advance(100.0 + 12 / 20)            # 12 frames after index 0: wrapped round to 2
    assert p.index == 2


def test_pause_holds_steps_pause_and_seeks_clamp(bake):
    p = BakePlayer(bake, bake.scene)
    p.play(now=0.0)
    p.advance(0.1)
    p.pause()
    assert not p.advance(5.0) and p.index == 2
    p.play(now=10.0)
    p.step(+1, now=10.0)
    assert not p.playing and p.index == 3
    p.seek(99, now=11.0)
    assert p.index == FRAMES - 1
    p.play(now=12.0)                      # at the end: from the beginning again
    assert p.index == 0 and p.playing
    p.seek(-5, now=13.0)
    assert p.index == 0


def test_the_snapshot_is_the_bakes_frame(bake):
    p = BakePlayer(bake, bake.scene)
    p.seek(6, now=0.0)
    snap = p.snapshot()
    assert snap.frame == 7 and snap.t == pytest.approx(7 / 20)
    np.testing.assert_array_equal(snap.positions, bake.positions(7))
    assert snap.objects == bake.objects(7) and len(snap.objects) == 1
    assert snap.model.num_particles == len(snap.positions)


def test_a_rectangular_bake_replays_its_grid(tmp_path):
    out = tmp_path / "r.usda"
    assert main(["bake", "default", "-o", str(out), "--frames", "3", "--set",
                 "cloth.size=[2, 0.5]", "--set", "cloth.resolution=[9, 4]"]) == 0
    bake = UsdBake(out)
    assert bake.grid == (9, 4)
    snap = BakePlayer(bake, bake.scene).snapshot()
    assert (snap.model.nx, snap.model.nz) == (9, 4)


def test_a_grid_that_is_not_the_scenes_is_refused(tmp_path):
    # Points of a 9 × 4 sheet with a scene that makes 4 × 9: the same count, another grid.
    from cloth_tui.usage import UsageError

    out = tmp_path / "r.usda"
    assert main(["bake", "default", "-o", str(out), "--frames", "2", "--set",
                 "cloth.size=[2, 0.5]", "--set", "cloth.resolution=[9, 4]"]) == 0
    bake = UsdBake(out)
    turned = bake.scene.with_values({"cloth.size": [0.5, 2.0], "cloth.resolution": [4, 9]})
    with pytest.raises(UsageError, match="9 × 4"):
        BakePlayer(bake, turned)


def test_a_bake_without_a_grid_replays_as_the_square_it_is(tmp_path):
    # Bakes made before rectangular sheets have no cloth_tui:grid: their scene decides.
    from pxr import Usd

    out = tmp_path / "old.usda"
    assert main(["bake", "default", "-o", str(out), "--frames", "2", "--set",
                 "cloth.resolution=6"]) == 0
    stage = Usd.Stage.Open(str(out))
    assert stage.GetPrimAtPath("/World/Cloth").RemoveProperty("cloth_tui:grid")
    stage.GetRootLayer().Save()
    bake = UsdBake(out)
    assert bake.grid is None
    snap = BakePlayer(bake, bake.scene).snapshot()
    assert (snap.model.nx, snap.model.nz) == (6, 6) and len(snap.positions) == 36
