"""The knife: a right-drag over the preview cuts the cloth; `torn` rises; restart heals."""

import time

import pytest

from cloth_tui.scene import Scene
from cloth_tui.tui.app import ClothApp, default_renderer_factory

from .conftest import SIZE, make_app, run, until


def torn(app) -> int:
    return app.sim.latest.stats.torn


async def settled(pilot, read, interval: float = 0.3, timeout: float = 10.0):
    """The value once it stops changing: the knife's cuts are commands the simulation thread
    applies between frames, so the count can still be rising when it is first above 0."""
    value, deadline = read(), time.monotonic() + timeout
    while time.monotonic() < deadline:
        await pilot.pause(interval)
        value, last = read(), value
        if value == last:
            return value
    raise AssertionError(f"still changing after {timeout} s")


def test_right_drag_cuts_the_cloth_and_restart_heals(tmp_path):
    async def go():
        app = make_app(tmp_path)
        async with app.run_test(size=SIZE) as pilot:
            await until(pilot, lambda: app.renderer.snapshot is not None)
            preview = app.preview
            w, h = preview.size.width, preview.size.height
            assert torn(app) == 0
            # the fake's front view: the flat sheet is the row of cells at mid-height
            y = h // 2
            await pilot.mouse_down("#preview", offset=(w // 3, y), button=3)
            assert app._grabbed is None  # the right button cuts, it does not grab
            for x in range(w // 3 + 1, 2 * w // 3, 2):
                await pilot.hover("#preview", offset=(x, y))
            await pilot.mouse_up("#preview", offset=(2 * w // 3, y))
            await until(pilot, lambda: torn(app) > 0, what="torn > 0")
            cut = await settled(pilot, lambda: torn(app))  # every queued cut applied
            assert app.sim.latest.alive is not None
            status = app.query_one("#status-text")
            await until(pilot, lambda: f"{cut} torn" in str(status.render()),
                        what="the status line shows the torn count")  # refreshed at 5 Hz
            # a left-drag still grabs and cuts nothing
            await pilot.mouse_down("#preview", offset=(w // 2, y))
            assert app._grabbed is not None
            await pilot.hover("#preview", offset=(w // 2 + 4, y))
            await pilot.mouse_up("#preview", offset=(w // 2 + 4, y))
            await pilot.pause(0.2)
            assert torn(app) == cut
            await pilot.press("r")
            await until(pilot, lambda: torn(app) == 0, what="healed")
            assert app.sim.latest.alive is None
    run(go())


def test_the_knife_cuts_through_the_real_renderer_and_the_picture_loses_faces(tmp_path):
    """With the real RenderService (skipped without GL): a right-drag across the crosshair
    (the sheet's middle) cuts, and the drawn mesh loses the cut cells."""
    pytest.importorskip("cloth_tui.render.service")

    async def go():
        app = ClothApp(Scene(), tmp_path / "caps", renderer_factory=default_renderer_factory,
                       start_paused=True)
        async with app.run_test(size=SIZE) as pilot:
            deadline = time.monotonic() + 20
            while app.preview.frames_shown == 0:
                if app.renderer is None or getattr(app.renderer, "error", None):
                    pytest.skip("renderer unavailable")
                assert time.monotonic() < deadline, "no frame from the renderer"
                await pilot.pause(0.05)
            await until(pilot, lambda: app._crosshair_placed, timeout=10)
            full = app.renderer._renderer.cloth.n_cells
            cx, cy = app.preview._cell(app.preview.crosshair)
            await pilot.mouse_down("#preview", offset=(cx - 12, cy), button=3)
            for x in range(cx - 11, cx + 13):
                await pilot.hover("#preview", offset=(x, cy))
            await pilot.mouse_up("#preview", offset=(cx + 12, cy))
            await until(pilot, lambda: torn(app) > 0, what="torn > 0")
            await until(pilot, lambda: app.renderer._renderer.cloth.n_cells < full,
                        timeout=10, what="faces dropped")
    run(go())
