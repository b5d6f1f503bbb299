"""`cloth-tui render BAKE.usd -o …`: a bake drawn again without simulating."""

import numpy as np
import pytest

from cloth_tui.cli import main

from .service_helpers import count_frames

pytest.importorskip("pxr")

SMALL = ["--set", "cloth.resolution=10"]


@pytest.fixture(scope="module")
def bake(tmp_path_factory):
    out = tmp_path_factory.mktemp("bake") / "s.usdc"
    assert main(["bake", "sphere", "-o", str(out), "--frames", "12", *SMALL]) == 0
    return out


@pytest.fixture
def no_simulation(monkeypatch):
    from cloth_tui.sim.run.runner import Simulation

    def refuse(self, *a, **k):
        raise AssertionError("a replay must not simulate")
    monkeypatch.setattr(Simulation, "advance_frame", refuse)


def test_video_has_every_baked_frame_without_simulating(bake, tmp_path, no_simulation):
    out = tmp_path / "r.gif"
    assert main(["render", str(bake), "-o", str(out), "--size", "64x48",
                 "--set", "appearance.wireframe=false"]) == 0
    assert count_frames(out) == 12


def test_png_of_the_bake_is_the_picture_of_the_simulation(bake, tmp_path):
    import imageio.v3 as iio

    direct, replay = tmp_path / "direct.png", tmp_path / "replay.png"
    assert main(["render", "sphere", "-o", str(direct), "--frames", "12", "--size", "96x72",
                 *SMALL]) == 0
    assert main(["render", str(bake), "-o", str(replay), "--size", "96x72"]) == 0
    a, b = iio.imread(direct).astype(int), iio.imread(replay).astype(int)
    assert a.shape == b.shape == (72, 96, 3)
    # float32 points may move an edge by a pixel, nothing more
    assert np.mean(np.abs(a - b)) < 0.5


def test_appearance_settings_change_the_picture(bake, tmp_path):
    import imageio.v3 as iio

    plain, blue = tmp_path / "plain.png", tmp_path / "blue.png"
    assert main(["render", str(bake), "-o", str(plain), "--size", "64x48"]) == 0
    assert main(["render", str(bake), "-o", str(blue), "--size", "64x48",
                 "--set", "appearance.cloth_color=#2040ff"]) == 0
    a, b = iio.imread(plain).astype(int), iio.imread(blue).astype(int)
    assert (b[..., 2] - a[..., 2]).max() > 50


@pytest.mark.parametrize("args", [["--set", "behavior.substeps=3"],
                                  ["--set", "cloth.resolution=5"]])
def test_physics_settings_are_refused_exit_2(bake, tmp_path, capsys, args):
    assert main(["render", str(bake), "-o", str(tmp_path / "x.png"), *args]) == 2
    err = capsys.readouterr().err
    assert err.count("\n") == 1 and "appearance" in err


def test_a_usd_file_that_is_no_bake_is_refused_exit_2(tmp_path, capsys):
    from pxr import Usd, UsdGeom
    other = tmp_path / "other.usda"
    stage = Usd.Stage.CreateNew(str(other))
    UsdGeom.Sphere.Define(stage, "/Ball")
    stage.GetRootLayer().Save()
    broken = tmp_path / "broken.usdc"
    broken.write_bytes(b"not usd at all")
    for path in (other, broken, tmp_path / "missing.usd"):
        assert main(["render", str(path), "-o", str(tmp_path / "x.png")]) == 2
        err = capsys.readouterr().err
        assert err.count("\n") == 1 and str(path.name) in err


def test_a_video_plays_at_the_bakes_own_frame_rate_unless_fps_is_given(tmp_path):
    import imageio.v2 as iio

    bake24 = tmp_path / "b24.usdc"
    assert main(["bake", "default", "-o", str(bake24), "--frames", "4",
                 "--set", "cloth.resolution=5", "--set", "behavior.frame_rate=24"]) == 0
    own, given = tmp_path / "own.mp4", tmp_path / "given.mp4"
    assert main(["render", str(bake24), "-o", str(own), "--size", "64x48"]) == 0
    assert main(["render", str(bake24), "-o", str(given), "--size", "64x48", "--fps", "10"]) == 0
    for path, fps in ((own, 24.0), (given, 10.0)):
        with iio.get_reader(str(path)) as reader:
            assert reader.get_meta_data()["fps"] == pytest.approx(fps)


RING_AND_POST = """
[cloth]
resolution = 10
height = 0.6

[[objects]]
type = "torus"
center = [0.0, 0.0, 0.0]
axis = [0.0, 1.0, 0.0]
major_radius = 0.3
minor_radius = 0.1

[[objects]]
type = "cylinder"
center = [0.0, 0.05, 0.0]
axis = [0.0, 1.0, 0.0]
radius = 0.08
height = 0.3
"""


def test_a_bake_of_a_torus_and_a_cylinder_replays_as_it_was_simulated(tmp_path):
    import imageio.v3 as iio

    scene = tmp_path / "ring.toml"
    scene.write_text(RING_AND_POST)
    bare = tmp_path / "bare.toml"
    bare.write_text(RING_AND_POST.split("[[objects]]")[0])
    out = tmp_path / "ring.usda"
    assert main(["bake", str(scene), "-o", str(out), "--frames", "6"]) == 0
    pictures = {}
    for name, args in (("direct", [str(scene), "--frames", "6"]), ("replay", [str(out)]),
                       ("bare", [str(bare), "--frames", "6"])):
        pictures[name] = tmp_path / f"{name}.png"
        assert main(["render", *args, "-o", str(pictures[name]), "--size", "96x72"]) == 0
    a, b, c = (iio.imread(pictures[k]).astype(int) for k in ("direct", "replay", "bare"))
    assert np.mean(np.abs(a - b)) < 0.5
    assert np.mean(np.abs(b - c)) > 2.0  # the replay draws both objects
