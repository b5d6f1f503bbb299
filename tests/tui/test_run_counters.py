"""The status line tells about the current run only: after `r`, a scene opened from the
palette, or a setting that rebuilds the sheet, a past run's retried frames are not shown."""

import numpy as np

from .conftest import SIZE, make_app, run, until


def diverge(sim) -> None:
    """A frame that blows up and is retried by the guard (one recovery)."""
    sim.state.x[3] = np.nan
    sim.state.v[3] = np.nan
    sim.advance_frame()


def status_text(app) -> str:
    return str(app.query_one("#status-text").render())


def test_recoveries_are_not_shown_after_the_run_that_had_them(tmp_path):
    async def go():
        app = make_app(tmp_path)
        async with app.run_test(size=SIZE) as pilot:
            async def recovered() -> None:
                app.sim.submit(diverge)
                await until(pilot, lambda: app.readout.stats.recoveries > 0,
                            what="a recovery in the status")
                app._refresh_status()
                await pilot.pause()
                assert "recoveries" in status_text(app)

            async def shown_clean(what: str) -> None:
                await until(pilot, lambda: app.readout.stats.recoveries == 0
                            and app.readout.stats.frames == 0, what=what)
                app._refresh_status()
                await pilot.pause()
                assert "recoveries" not in status_text(app)

            await recovered()
            await pilot.press("r")
            await shown_clean("no recoveries after r")

            await recovered()
            app.open_scene("sphere")  # what the palette's "Open scene: sphere" calls
            await shown_clean("no recoveries in the newly opened scene")

            await recovered()
            assert app.set_value("cloth.resolution", 14)
            await shown_clean("no recoveries after a new resolution")
            await pilot.press("q")

    run(go())
