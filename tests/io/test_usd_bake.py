"""`cloth-tui bake … -o OUT.usd(c/a)`: what pxr reads back is the simulation."""

import os
import signal
import subprocess
import sys
import threading
import time

import numpy as np
import pytest

from cloth_tui.cli import main
from cloth_tui.scene_files import apply_overrides, load, loads

from .helpers import simulated_frames

pxr = pytest.importorskip("pxr")
from pxr import Sdf, Usd, UsdGeom  # noqa: E402

SMALL = ["--set", "cloth.resolution=10"]


def _open(path):
    stage = Usd.Stage.Open(str(path))
    assert stage is not None
    return stage


def test_sphere_bake_reads_back_as_the_simulation(tmp_path):
    out = tmp_path / "s.usdc"
    assert main(["bake", "sphere", "-o", str(out), "--frames", "12", *SMALL]) == 0
    stage = _open(out)
    assert UsdGeom.GetStageUpAxis(stage) == UsdGeom.Tokens.y
    assert UsdGeom.GetStageMetersPerUnit(stage) == 1.0
    scene = apply_overrides(load("sphere"), SMALL[1::2])
    assert stage.GetTimeCodesPerSecond() == scene.behavior.frame_rate
    assert (stage.GetStartTimeCode(), stage.GetEndTimeCode()) == (1, 12)
    assert loads(stage.GetRootLayer().customLayerData["cloth_tui:scene"]) == scene

    cloth = UsdGeom.Mesh.Get(stage, "/World/Cloth")
    points = cloth.GetPointsAttr()
    assert points.GetTimeSamples() == [float(k) for k in range(1, 13)]
    xs, poses = simulated_frames("sphere", SMALL[1::2], 12)
    for k, x in enumerate(xs, start=1):
        got = np.asarray(points.Get(float(k)))
        np.testing.assert_allclose(got, x, rtol=0, atol=1e-6)
        normals = np.asarray(cloth.GetNormalsAttr().Get(float(k)))
        assert normals.shape == x.shape
        np.testing.assert_allclose(np.linalg.norm(normals, axis=1), 1.0, atol=1e-5)
    assert not np.allclose(xs[0], xs[-1])  # the sheet moved: samples are frames, not copies
    n = scene.cloth.resolution
    assert list(cloth.GetFaceVertexCountsAttr().Get()) == [3] * (2 * (n - 1) ** 2)
    st = UsdGeom.PrimvarsAPI(cloth).GetPrimvar("st")
    assert st.GetInterpolation() == UsdGeom.Tokens.vertex and len(st.Get()) == n * n

    sphere = UsdGeom.Sphere.Get(stage, "/World/Objects/Object_0/Shape")
    radius = poses[0][0].parameters["radius"]
    assert sphere and sphere.GetRadiusAttr().Get() == pytest.approx(radius)
    centre = UsdGeom.Xformable(sphere.GetPrim()).ComputeLocalToWorldTransform(1.0)
    np.testing.assert_allclose(centre.ExtractTranslation(), poses[0][0].center)
    ground = UsdGeom.Mesh.Get(stage, "/World/Ground")
    assert np.asarray(ground.GetPointsAttr().Get())[:, 1] == pytest.approx(
        scene.scene.floor_height)


def test_moving_object_has_time_sampled_translate_and_still_one_none(tmp_path):
    out = tmp_path / "m.usda"
    sets = ["cloth.resolution=6", "scene.object=capsule", "scene.moving=true"]
    args = [a for s in sets for a in ("--set", s)]
    assert main(["bake", "default", "-o", str(out), "--frames", "5", *args]) == 0
    stage = _open(out)
    translate = UsdGeom.Xformable(stage.GetPrimAtPath("/World/Objects/Object_0")
                                  ).GetOrderedXformOps()[0]
    assert translate.GetAttr().GetTimeSamples() == [1.0, 2.0, 3.0, 4.0, 5.0]
    _, poses = simulated_frames("default", sets, 5)
    for k in range(1, 6):
        np.testing.assert_allclose(translate.Get(float(k)), poses[k - 1][0].center)
    capsule = UsdGeom.Capsule.Get(stage, "/World/Objects/Object_0/Shape")
    # The capsule's own axis (z) turned onto the scene's axis.
    local = capsule.GetLocalTransformation()
    axis = np.asarray(local.TransformDir((0.0, 0.0, 1.0)))
    np.testing.assert_allclose(axis, poses[0][0].parameters["axis"], atol=1e-6)

    still = tmp_path / "still.usda"
    assert main(["bake", "box", "-o", str(still), "--frames", "3",
                 "--set", "cloth.resolution=6"]) == 0
    stage = _open(still)
    op = UsdGeom.Xformable(stage.GetPrimAtPath("/World/Objects/Object_0")).GetOrderedXformOps()[0]
    assert op.GetAttr().GetTimeSamples() == []
    assert UsdGeom.Cube.Get(stage, "/World/Objects/Object_0/Shape")


def test_missing_usd_core_names_the_extra_exit_2(tmp_path, capsys, monkeypatch):
    monkeypatch.setitem(sys.modules, "pxr", None)  # import pxr → ImportError
    monkeypatch.setitem(sys.modules, "pxr.Usd", None)
    assert main(["bake", "sphere", "-o", str(tmp_path / "s.usdc"), "--frames", "2"]) == 2
    err = capsys.readouterr().err
    assert err.count("\n") == 1 and "cloth-tui[usd]" in err
    assert not (tmp_path / "s.usdc").exists()


@pytest.mark.parametrize("out", ["x.abc", "/no/such/folder/x.usdc", "/sys/x.usdc"])
def test_bad_output_is_one_line_exit_2(tmp_path, capsys, out):
    out = out if out.startswith("/") else str(tmp_path / out)
    assert main(["bake", "sphere", "-o", out, "--frames", "2"]) == 2
    err = capsys.readouterr().err
    assert err.count("\n") == 1 and "error" in err


def _start_bake(out):
    """A long bake, its stderr read on (a full pipe would stall it) into `proc.err`."""
    env = dict(os.environ, PYTHONUNBUFFERED="1")
    proc = subprocess.Popen([sys.executable, "-m", "cloth_tui", "bake", "sphere", "-o",
                             str(out), "--frames", "10000000", "--set", "cloth.resolution=12"],
                            stdout=subprocess.DEVNULL, stderr=subprocess.PIPE, env=env)
    proc.err = bytearray()
    proc.reader = threading.Thread(target=lambda: proc.err.extend(proc.stderr.read()),
                                   daemon=True)
    proc.reader.start()
    return proc


STALL_S = 300.0  # bounds a failing test only: a loaded machine can take minutes to start


def _saved_frames(out) -> int:
    """Frames in the file now, read from disk afresh (not a layer USD kept open)."""
    layer = Sdf.Layer.OpenAsAnonymous(str(out))
    if layer is None:
        return 0
    stage = Usd.Stage.Open(layer)
    return UsdGeom.Mesh.Get(stage, "/World/Cloth").GetPointsAttr().GetNumTimeSamples()


def _wait_for_saved_frames(proc, out, minimum=2) -> int:
    """Waits, while the bake runs, for a save with at least `minimum` frames: each save
    replaces the file, so its change is the event looked for."""
    deadline = time.monotonic() + STALL_S
    seen = None
    while time.monotonic() < deadline and proc.poll() is None:
        stamp = out.stat().st_mtime_ns if out.exists() else None
        if stamp is not None and stamp != seen:
            seen = stamp
            samples = _saved_frames(out)
            if samples >= minimum:
                return samples
        time.sleep(0.1)
    proc.kill()
    pytest.fail(f"no {minimum} frames were saved to {out}; the bake said {bytes(proc.err)!r}")


def _check_frames_are_the_simulation(out) -> int:
    stage = Usd.Stage.Open(Sdf.Layer.OpenAsAnonymous(str(out)))
    points = UsdGeom.Mesh.Get(stage, "/World/Cloth").GetPointsAttr()
    samples = points.GetTimeSamples()
    n = len(samples)
    assert samples == [float(k) for k in range(1, n + 1)]
    assert stage.GetEndTimeCode() == n  # the saved stage says how far it got
    xs, _ = simulated_frames("sphere", ["cloth.resolution=12"], n)
    for k in (1, n):
        np.testing.assert_allclose(np.asarray(points.Get(float(k))), xs[k - 1], atol=1e-6)
    return n


def test_sigkill_leaves_a_readable_bake_with_the_frames_done(tmp_path):
    out = tmp_path / "killed.usdc"
    proc = _start_bake(out)
    seen = _wait_for_saved_frames(proc, out)
    assert proc.poll() is None, "the bake ended before it was killed"
    proc.send_signal(signal.SIGKILL)
    proc.wait(STALL_S)
    assert _check_frames_are_the_simulation(out) >= seen


@pytest.mark.parametrize("sig,status", [(signal.SIGINT, 130), (signal.SIGTERM, 143)])
def test_interrupt_finishes_the_bake(tmp_path, sig, status):
    out = tmp_path / "stopped.usda"
    proc = _start_bake(out)
    _wait_for_saved_frames(proc, out)
    assert proc.poll() is None, "the bake ended before it was interrupted"
    proc.send_signal(sig)
    proc.wait(STALL_S)  # it finishes the frame under way and saves
    proc.reader.join(STALL_S)
    assert proc.returncode == status
    err = proc.err.decode().strip()
    assert err.count("\n") == 0 and "saved" in err
    n = _check_frames_are_the_simulation(out)
    assert f"stopped after {n} of" in err  # every frame done is in the file
    assert [p.name for p in tmp_path.iterdir()] == ["stopped.usda"]  # no temp left


def test_saves_thin_out_when_they_grow_slow(tmp_path, monkeypatch):
    """Each save rewrites the whole stage: on a long bake it must not eat the run. A save
    that took 2 s is followed by the next only 2 / SAVE_SHARE = 10 s later (a fake clock)."""
    from cloth_tui.io import usd_bake
    from cloth_tui.io.frames import BakedFrame
    from cloth_tui.sim.model import build_model

    class Clock:
        t = 0.0

        def monotonic(self):
            return self.t

    clock = Clock()
    monkeypatch.setattr(usd_bake, "time", clock)
    saves = []

    class SlowReplaceOs:
        """usd_bake's own `os`, with a replace that takes 2 s of the fake clock. Not the os
        module itself: a thread left by another test that renames a file would count."""

        def __getattr__(self, name):
            return getattr(os, name)

        def replace(self, src, dst):
            saves.append(clock.t)
            clock.t += 2.0
            os.replace(src, dst)
    monkeypatch.setattr(usd_bake, "os", SlowReplaceOs())
    scene = apply_overrides(load("sphere"), ["cloth.resolution=4"])
    model = build_model(scene.cloth, scene.behavior)
    writer = usd_bake.UsdBakeWriter(tmp_path / "s.usdc", scene, model)
    for k in range(1, 41):
        clock.t += 0.5
        writer.write(BakedFrame(k, k / 60, model.rest_positions, ()))
    assert saves[0] == 1.0  # the first after SAVE_INTERVAL_S
    assert all(b - a >= 2.0 + 2.0 / usd_bake.SAVE_SHARE for a, b in zip(saves, saves[1:]))
    assert len(saves) >= 2


RECT = ["cloth.size=[1.5, 0.5]", "cloth.resolution=[31, 11]"]


def test_a_3_to_1_bake_reads_back_as_simulate_dump(tmp_path):
    # The same run two ways: the bake's last frame, read with pxr, is the dump's positions
    # (to float32), and the bake says its grid is 31 × 11, rows of 31.
    args = [a for s in RECT for a in ("--set", s)]
    out, dump = tmp_path / "banner.usdc", tmp_path / "banner.npz"
    assert main(["bake", "default", "-o", str(out), "--frames", "15", *args]) == 0
    assert main(["simulate", "default", "--frames", "15", "--dump", str(dump), *args]) == 0
    d = np.load(dump)
    assert tuple(d["shape"]) == (11, 31)
    stage = _open(out)
    cloth = UsdGeom.Mesh.Get(stage, "/World/Cloth")
    assert tuple(cloth.GetPrim().GetAttribute("cloth_tui:grid").Get()) == (31, 11)
    got = np.asarray(cloth.GetPointsAttr().Get(15.0), dtype=np.float64)
    np.testing.assert_allclose(got, d["positions"], rtol=0, atol=1e-6)
    grid = got.reshape(11, 31, 3)
    assert np.ptp(grid[0, :, 0]) > 1.2 and np.ptp(grid[:, 0, 2]) < 0.6  # x along the rows
    assert list(cloth.GetFaceVertexCountsAttr().Get()) == [3] * (2 * 30 * 10)
    st = np.asarray(UsdGeom.PrimvarsAPI(cloth).GetPrimvar("st").Get()).reshape(11, 31, 2)
    np.testing.assert_allclose(st[0, [0, -1], 0], [0.0, 1.0], atol=1e-7)  # u: the width
    np.testing.assert_allclose(st[[0, -1], 0, 1], [2 / 3, 1 / 3], atol=1e-7)  # v: its third
