"""A bake is user input: `render BAKE` and the replay app refuse anything a cloth-tui bake
never holds in one line (exit 2), before any work, and never block or follow other files."""

import subprocess
import sys

import numpy as np
import pytest

from cloth_tui.cli import main

from . import hostile_bakes as hostile

pytest.importorskip("pxr")


def bake_of(folder, kind: str):
    """A short bake of the default scene with the single object `kind` (Object_0)."""
    out = folder / f"{kind}.usda"
    if not out.exists():
        assert main(["bake", "default", "-o", str(out), "--frames", "4",
                     "--set", "cloth.resolution=5", "--set", f"scene.object={kind}"]) == 0
    return out


@pytest.fixture(scope="module")
def bakes(tmp_path_factory):
    """kind → a bake with that object, made once per module."""
    folder = tmp_path_factory.mktemp("bakes")
    return lambda kind: bake_of(folder, kind)


@pytest.fixture(scope="module")
def bake(bakes):
    return bakes("sphere")


# which recorded shape holds each attribute the tests below spoil
HOLDER = {"radius": "sphere", "type": "sphere", "size": "box", "axis": "capsule"}


def refused(capfd, path, says, command="render"):
    args = ["render", str(path), "-o", str(path.with_suffix(".mp4"))] if command == "render" \
        else [str(path), "--captures", str(path.parent / "caps")]
    capfd.readouterr()  # what making the hostile file printed
    rc = main(args)
    out, err = capfd.readouterr()
    assert rc == 2 and err.count("\n") == 1 and says in err, (rc, err)
    assert list(path.parent.glob("*.mp4")) == []  # nothing begun, no .partial.mp4 left


@pytest.mark.parametrize("rate", [0.0, -30.0, 1e-300, 1e300, float("inf")])
@pytest.mark.parametrize("command", ["render", "app"])
def test_frame_rates_no_bake_has_are_refused(tmp_path, capfd, bake, rate, command):
    path = hostile.frame_rate(bake, tmp_path / "r.usda", rate)
    refused(capfd, path, "timeCodesPerSecond", command)


@pytest.mark.parametrize("name", ["radius", "size", "type"])
def test_an_object_missing_an_attribute_is_refused(tmp_path, capfd, bakes, name):
    path = hostile.drop_attribute(bakes(HOLDER[name]), tmp_path / "o.usda", name)
    if name == "type":  # no type: not a cloth-tui object, drawn as nothing, still fine
        assert main(["render", str(path), "-o", str(tmp_path / "o.png")]) == 0
        return
    refused(capfd, path, f"cloth_tui:{name} is missing")


@pytest.mark.parametrize("name, value, type_name, says", [
    ("radius", "big", "String", "cloth_tui:radius"),
    ("radius", float("nan"), "Double", "cloth_tui:radius"),
    ("axis", (0.0, 0.0, 0.0), "Double3", "too short to give a direction"),
    ("size", (1.0, -1.0, 1.0), "Double3", "none negative"),
    ("type", "teapot", "String", "cloth_tui:type = 'teapot'")])
def test_object_attributes_of_the_wrong_type_or_value_are_refused(tmp_path, capfd, bakes,
                                                                   name, value, type_name, says):
    refused(capfd, hostile.object_value(bakes(HOLDER[name]), tmp_path / "o.usda", name, value,
                                        type_name), says)


@pytest.mark.parametrize("value", [5, 2.5, True])
def test_a_recorded_scene_that_is_not_text_is_refused(tmp_path, capfd, bake, value):
    refused(capfd, hostile.recorded_scene(bake, tmp_path / "s.usda", value), "recorded scene")


@pytest.mark.parametrize("count", [3, 10_000])
@pytest.mark.parametrize("command", ["render", "app"])
def test_intact_flags_that_do_not_fit_the_sheet_are_refused(tmp_path, capfd, bake, count,
                                                            command):
    from cloth_tui.io.usd_read import UsdBake
    from cloth_tui.sim.model import build_model

    scene = UsdBake(bake).scene
    fits = build_model(scene.cloth, scene.behavior).num_constraints
    path = hostile.alive_flags(bake, tmp_path / "a.usda", count, last_count=fits)
    refused(capfd, path, "cloth_tui:alive is not one 0/1 flag per constraint", command)


@pytest.mark.parametrize("value, says", [
    (np.full((25, 3), np.nan), "not finite"), (np.zeros((7, 3)), "frame 3 has 7 cloth points")])
def test_a_frame_of_bad_points_is_refused_before_the_video_begins(tmp_path, capfd, bake, value,
                                                                  says):
    refused(capfd, hostile.points(bake, tmp_path / "p.usda", 3.0, value), says)


@pytest.mark.parametrize("kind", ["sublayer", "reference", "payload"])
def test_composition_arcs_are_refused_without_being_followed(tmp_path, bake, kind):
    """Even to a FIFO, which would block a reader for ever: a child process, so that a
    hang fails the test instead of stopping the suite."""
    path = hostile.with_arc(bake, tmp_path / "c.usda", kind, hostile.fifo(tmp_path))
    run = subprocess.run([sys.executable, "-m", "cloth_tui", "render", str(path), "-o",
                          str(tmp_path / "c.png")], capture_output=True, text=True, timeout=60)
    assert run.returncode == 2 and run.stderr.count("\n") == 1, run.stderr
    assert ("sublayers" if kind == "sublayer" else "/World/Extra has") in run.stderr
    assert "Warning" not in run.stderr


def test_a_fifo_given_as_the_bake_is_refused(tmp_path, capfd):
    refused(capfd, hostile.fifo(tmp_path, "b.usdc"), "not a regular file")


def test_the_replay_app_ticks_at_most_60_times_a_second_at_any_bake_rate(tmp_path,
                                                                         monkeypatch):
    """A timer at the bake's 10⁴ frames/s left the app no time for keys or SIGTERM."""
    from cloth_tui.io.usd_read import UsdBake
    from cloth_tui.tui.replay_app import ReplayApp
    from tests.tui.conftest import SIZE, run
    from tests.tui.fakes import FakeRenderService

    out = tmp_path / "fast.usdc"
    assert main(["bake", "default", "-o", str(out), "--frames", "30", "--set",
                 "cloth.resolution=4", "--set", "behavior.frame_rate=10000"]) == 0
    ticks = []
    real_tick = ReplayApp._tick
    monkeypatch.setattr(ReplayApp, "_tick", lambda self: (ticks.append(1), real_tick(self)))
    bake = UsdBake(out)

    async def go():
        app = ReplayApp(bake.scene, tmp_path / "caps", bake=bake,
                        renderer_factory=FakeRenderService, start_paused=False)
        async with app.run_test(size=SIZE) as pilot:
            await pilot.pause(1.0)
            assert app.player.playing and 0 < len(ticks) <= 70
            await pilot.press("q")
    run(go())
