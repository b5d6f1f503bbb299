"""In a browser (`cloth-tui serve`) the app's simulation waits for the first picture shown,
so a visitor whose page shows it seconds after the app started sees the sheet fall."""

import threading

from cloth_tui.scene import Scene

from .conftest import SIZE, make_app, run, until
from .fakes import FakeRenderService


class HeldRenderService(FakeRenderService):
    """Draws nothing until `release` is set: a renderer still starting up."""

    release = threading.Event()

    def _draw(self):
        if self.release.is_set():
            super()._draw()


def _small() -> Scene:
    return Scene().with_value("cloth.resolution", 8)


def test_the_simulation_starts_when_the_first_picture_is_shown(tmp_path):
    HeldRenderService.release.clear()

    async def go():
        app = make_app(tmp_path, _small(), renderer_factory=HeldRenderService,
                       start_paused=False, start_when_shown=True)
        async with app.run_test(size=SIZE) as pilot:
            await pilot.pause(0.5)
            assert app.sim.paused and app.sim.latest.frame == 0  # no picture yet
            HeldRenderService.release.set()
            app.renderer.update_scene(app.scene)  # the renderer's first frame
            await until(pilot, lambda: app.preview.frames_shown > 0, what="a frame shown")
            await until(pilot, lambda: app.sim.latest.frame > 5, what="the sheet to move")
            assert not app.sim.paused

    run(go())


def test_without_a_renderer_the_simulation_starts_at_once(tmp_path):
    def no_renderer(**_):
        raise RuntimeError("no GL here")

    async def go():
        app = make_app(tmp_path, _small(), renderer_factory=no_renderer,
                       start_paused=False, start_when_shown=True)
        async with app.run_test(size=SIZE) as pilot:
            await until(pilot, lambda: app.sim.latest.frame > 5, what="the sheet to move")

    run(go())


def test_space_before_the_first_picture_is_the_users_choice(tmp_path):
    """Paused, then unpaused by the user before any picture: the first picture does not
    pause or unpause it again."""
    HeldRenderService.release.clear()

    async def go():
        app = make_app(tmp_path, _small(), renderer_factory=HeldRenderService,
                       start_paused=False, start_when_shown=True)
        async with app.run_test(size=SIZE) as pilot:
            await pilot.press("space")  # runs now
            await pilot.press("space")  # and pauses: the user wants it still
            await pilot.pause(0.3)
            HeldRenderService.release.set()
            app.renderer.update_scene(app.scene)
            await until(pilot, lambda: app.preview.frames_shown > 0, what="a frame shown")
            await pilot.pause(0.5)
            assert app.sim.paused

    run(go())
