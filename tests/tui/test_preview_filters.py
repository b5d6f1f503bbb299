"""The preview leaves out Textual's ANSIToTruecolor line filter (tui/preview.py): its strips
hold RGB colours only, so the filter would change nothing there, at the cost of copying
every changed row's segments each frame. Every other filter of the app still applies, and
NO_COLOR's Monochrome filter, which reads every segment's style, finds one on each (an
unstyled placeholder row once ended `NO_COLOR=1 cloth-tui` with an internal error)."""

import numpy as np
from rich.terminal_theme import DEFAULT_TERMINAL_THEME
from textual.app import App
from textual.color import Color
from textual.filter import ANSIToTruecolor, Monochrome

from cloth_tui.tui.preview import Preview, StyleCache, image_to_strips

from .conftest import run


class PreviewOnly(App):
    def compose(self):
        yield Preview(id="preview")


def test_the_preview_drops_the_ansi_filter_and_draws_under_no_color(monkeypatch):
    monkeypatch.setenv("NO_COLOR", "1")  # the app then adds its Monochrome filter

    async def go():
        app = PreviewOnly()
        async with app.run_test(size=(40, 12)) as pilot:
            await pilot.pause()  # the placeholder drawn through every filter
            app_filters = list(app.get_line_filters())
            own = list(app.query_one(Preview).get_line_filters())
            assert any(isinstance(f, ANSIToTruecolor) for f in app_filters)
            assert own == [f for f in app_filters if not isinstance(f, ANSIToTruecolor)]
            assert any(isinstance(f, Monochrome) for f in own)

    run(go())


def test_the_ansi_filter_would_leave_every_preview_strip_as_it_is():
    image = np.random.default_rng(5).integers(0, 256, size=(24, 30, 3), dtype=np.uint8)
    strips = image_to_strips(image, 30, 12, StyleCache(), crosshair=(4, 3))
    ansi = ANSIToTruecolor(DEFAULT_TERMINAL_THEME)
    for strip in strips:
        filtered = strip.apply_filter(ansi, Color(0, 0, 0))
        assert [(s.text, s.style) for s in filtered] == [(s.text, s.style) for s in strip]
