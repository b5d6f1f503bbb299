"""Pilot tests: the layout fits the terminal. Below 120 columns the preview takes the width and
the controls are a drawer (`c`); at 80×24 the status line (fps, stretch, energy) and the
footer are whole."""

from textual.widgets import Footer
from textual.widgets._footer import FooterKey

from .conftest import make_app, run, until


def _cells(widget) -> int:
    return widget.render().cell_length


def test_80x24_preview_takes_the_width_and_status_and_footer_fit(tmp_path):
    async def go():
        app = make_app(tmp_path)
        async with app.run_test(size=(80, 24)) as pilot:
            await until(pilot, lambda: app.preview.frames_shown > 0, what="a frame")
            app._refresh_status()
            await pilot.pause(0.1)
            assert not app.controls.display
            assert app.preview.size.width == 80

            status = app.query_one("#status-text")
            text = str(status.render())
            for shown in ("fps", "stretch", "E ", "ΔE"):
                assert shown in text
            assert _cells(status) <= status.size.width
            cost = app.query_one("#cost-text")
            assert "ms/frame" in str(cost.render()) and cost.region.right <= 80

            keys = list(app.query_one(Footer).query(FooterKey))
            assert keys and all(k.region.right <= 80 and k.region.width > 0 for k in keys)
            labels = {k.description for k in keys}
            assert {"Help", "Controls", "Pause", "Quit"} <= labels

            await pilot.press("c")  # the drawer opens over the preview
            await pilot.pause(0.1)
            assert app.controls.display and app.controls.region.right == 80
            assert app.preview.size.width == 80
            await pilot.press("c")
            await pilot.pause(0.1)
            assert not app.controls.display

            await pilot.resize_terminal(160, 48)  # wide: the panel sits beside the preview
            await pilot.pause(0.2)
            assert app.controls.display
            assert app.preview.size.width + app.controls.outer_size.width == 160
    run(go())
