"""The app with the real RenderService (VTK off-screen): frames reach the preview, `i` writes a
PNG, `v` … `v` writes an MP4, an arrow bumps the particle under the crosshair, a drag from
behind the sheet follows the camera, `q` quits.
Skipped when the renderer cannot start here (no GL)."""

import time

import pytest

from cloth_tui.scene import Scene
from cloth_tui.tui.app import ClothApp, default_renderer_factory

from .conftest import SIZE, notifications, run, until


def test_real_renderer_end_to_end(tmp_path):
    pytest.importorskip("cloth_tui.render.service")
    caps = tmp_path / "caps"

    async def go():
        app = ClothApp(Scene(), caps, renderer_factory=default_renderer_factory)
        async with app.run_test(size=SIZE) as pilot:
            deadline = time.monotonic() + 20
            while app.preview.frames_shown == 0:
                if app.renderer is None or getattr(app.renderer, "error", None):
                    pytest.skip(f"renderer unavailable: {notifications(app)}")
                assert time.monotonic() < deadline, "no frame from the renderer"
                await pilot.pause(0.05)
            await until(pilot, lambda: app._crosshair_placed, timeout=10)
            await pilot.press("i")
            await until(pilot, lambda: list(caps.glob("*.png")) and
                        any("Screenshot saved" in m for m in notifications(app)), timeout=10)
            await pilot.press("v")
            await pilot.pause(0.8)
            await pilot.press("v")
            await until(pilot, lambda: any("Video saved" in m for m in notifications(app)),
                        timeout=10)
            assert [p for p in caps.glob("*.mp4") if p.stat().st_size > 0]
            await pilot.press("space")  # paused: only the bump moves the sheet
            target = app.renderer.pick(*app.preview.target)
            assert target is not None
            y0 = app.sim.latest.positions[target][1]
            await pilot.press("up")
            await until(pilot, lambda: app.sim.latest.positions[target][1] > y0 + 0.04)
            # seen from behind (orbit 180°), dragging right pulls the particle towards -x
            az = app.renderer._renderer.camera.azimuth
            app.renderer.orbit(180, 0)
            await until(pilot, lambda: abs(app.renderer._renderer.camera.azimuth - az) > 1)
            await pilot.pause(0.3)  # the redraw that saves the orbited camera for picking
            assert app._place_crosshair()
            cx, cy = app.preview._cell(app.preview.crosshair)
            await pilot.mouse_down("#preview", offset=(cx, cy))
            grabbed = app._grabbed
            assert grabbed is not None
            x0 = app.sim.latest.positions[grabbed].copy()
            await pilot.hover("#preview", offset=(cx + 8, cy))
            await until(pilot, lambda: app.sim.latest.positions[grabbed][0] < x0[0] - 0.02)
            await pilot.mouse_up("#preview", offset=(cx + 8, cy))
            t0 = time.monotonic()
            await pilot.press("q")
        assert time.monotonic() - t0 < 2.0
        assert app.return_code == 0 and not app.renderer._thread.is_alive()
    run(go())
