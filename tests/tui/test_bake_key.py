"""`e` in the live app records the simulation to a USD bake that reads back."""

import numpy as np
import pytest

from cloth_tui.scene import Scene

from .conftest import SIZE, make_app, notifications, run, until

pytest.importorskip("pxr")
from pxr import Usd, UsdGeom  # noqa: E402


def _small() -> Scene:
    return Scene().with_values({"cloth.resolution": 8})


def _read(path):
    stage = Usd.Stage.Open(str(path))
    points = UsdGeom.Mesh.Get(stage, "/World/Cloth").GetPointsAttr()
    return stage, points


def _bakes(app):
    return sorted(app.captures_dir.glob("bake-*.usdc"))


def test_e_starts_and_stops_a_bake_that_reads_back(tmp_path):
    async def go():
        # Paused until the bake starts: a machine slow to start the app would otherwise give
        # the sheet time to come to rest before the first frame recorded.
        app = make_app(tmp_path, _small(), start_paused=True)
        async with app.run_test(size=SIZE) as pilot:
            await pilot.press("e")
            await until(pilot, lambda: app.bake.recording, what="bake started")
            await pilot.press("space")
            await until(pilot, lambda: app.bake.recording and app.bake.recorder.frames >= 10,
                        timeout=20, what="frames recorded")
            app._refresh_status()
            assert "● USD" in str(app.query_one("#status-text").render())
            recorder = app.bake.recorder
            await pilot.press("e")
            await until(pilot, lambda: app.bake.recorder is None, timeout=20,
                        what="bake saved")
            assert "● USD" not in str(app.query_one("#status-text").render())
            # the notice is a message the app handles after the status line saw the save
            await until(pilot, lambda: any(m.startswith("Bake saved") for m in notifications(app)),
                        what="'Bake saved' notice")
            (path,) = _bakes(app)
            assert path == recorder.path
            stage, points = _read(path)
            samples = points.GetTimeSamples()
            assert len(samples) == recorder.frames >= 10
            assert samples == [float(k) for k in range(1, len(samples) + 1)]
            first, last = np.asarray(points.Get(1.0)), np.asarray(points.Get(samples[-1]))
            assert first.shape == (64, 3) and np.isfinite(last).all()
            assert not np.allclose(first, last)  # the sheet fell while recording
            assert stage.GetEndTimeCode() == samples[-1]
    run(go())


def test_a_new_sheet_ends_the_bake_and_quit_saves_a_running_one(tmp_path):
    async def go():
        app = make_app(tmp_path, _small(), start_paused=False)
        async with app.run_test(size=SIZE) as pilot:
            await pilot.press("e")
            await until(pilot, lambda: app.bake.recording and app.bake.recorder.frames >= 3,
                        timeout=20, what="frames recorded")
            await pilot.press("r")  # restart: a new sheet cannot go on in the same mesh
            await until(pilot, lambda: app.bake.recorder is None, timeout=20,
                        what="bake ended")
            # the notice is posted by the status refresh that ends the bake: wait for it
            await until(pilot, lambda: any("sheet was rebuilt" in m for m in notifications(app)),
                        timeout=30, what=f"the rebuilt notice among {notifications(app)}")
            await pilot.press("e")
            await until(pilot, lambda: app.bake.recording and app.bake.recorder.frames >= 3,
                        timeout=20, what="second bake")
            await pilot.press("q")
        bakes = _bakes(app)
        assert len(bakes) == 2
        for path in bakes:
            _, points = _read(path)
            assert points.GetNumTimeSamples() >= 3
    run(go())
