"""Without a working OpenGL driver the app still simulates and says there is no preview;
nothing crashes (the real renderer service, with its probe failing for real)."""

import pytest

from cloth_tui.render import probe
from cloth_tui.scene import Scene
from cloth_tui.tui.app import ClothApp, default_renderer_factory
from cloth_tui.tui.preview import Preview

from .conftest import SIZE, notifications, run, until


@pytest.fixture
def no_gl(monkeypatch):
    """No EGL vendor library for the probe's child process; this process's GL (if any was
    opened by other tests) is untouched, and the next probe runs afresh."""
    monkeypatch.setenv("__EGL_VENDOR_LIBRARY_FILENAMES", "/nonexistent.json")
    probe.renderer_problem.cache_clear()
    yield
    probe.renderer_problem.cache_clear()


def _status(app) -> str:
    return str(app.query_one("#status-text").render())


def _preview_text(app) -> str:
    preview = app.query_one(Preview)
    return " ".join("".join(seg.text for seg in preview.render_line(y)).strip()
                    for y in range(preview.size.height))


def test_app_without_gl_simulates_and_says_there_is_no_preview(tmp_path, no_gl):
    async def go():
        app = ClothApp(Scene(), tmp_path / "caps", renderer_factory=default_renderer_factory)
        async with app.run_test(size=SIZE) as pilot:
            await until(pilot, lambda: "no preview" in _status(app), timeout=60,
                        what="'no preview' in the status line")
            assert "libegl-mesa0" in _preview_text(app)
            assert "waiting for the renderer" not in _preview_text(app)
            await until(pilot, lambda: any("No preview" in n for n in notifications(app)),
                        what="'No preview' notice")
            frame = app.sim.latest.frame
            await until(pilot, lambda: app.sim.latest.frame > frame + 10, timeout=30,
                        what="the simulation running on")
            await pilot.press("i")  # a screenshot is refused with a message, not a crash
            await pilot.press("q")
        assert app.return_code == 0
    run(go())
