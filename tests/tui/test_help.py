"""Pilot test: `?` and F1 open the help screen, which lists every app key (read from the
bindings) and the mouse actions, by group; Escape closes it."""

import pytest
from textual.binding import Binding
from textual.geometry import Region

from cloth_tui.tui.bindings import APP_BINDINGS, KEY_GROUPS, MOUSE_ACTIONS
from cloth_tui.tui.help import HelpScreen, help_groups, key_text
from cloth_tui.tui.panels import SettingField

from .conftest import SIZE, make_app, run, until


def test_help_lists_every_key_and_mouse_action_by_group(tmp_path):
    async def go():
        app = make_app(tmp_path)
        async with app.run_test(size=SIZE) as pilot:
            await pilot.press("question_mark")
            assert isinstance(app.screen, HelpScreen)
            groups = help_groups(app)
            assert list(groups)[:len(KEY_GROUPS)] == list(KEY_GROUPS)
            rows = [row for rows in groups.values() for row in rows]
            for binding in APP_BINDINGS:
                if binding.action == "unfocus":  # Escape: listed as the fields' Escape
                    continue
                assert (key_text(app, binding), binding.tooltip) in rows
            assert key_text(app, Binding("up,pageup", "x")) == "↑ / pgup"
            escape = SettingField.BINDINGS[0]
            assert (key_text(app, escape), escape.description) in groups["Fields"]
            assert ("⏎", "apply the value and move to the next field") in groups["Fields"]
            assert groups["Mouse"] == MOUSE_ACTIONS

            wireframe = app.scene.appearance.wireframe
            await pilot.press("w")  # nothing acts unseen behind the help
            assert app.scene.appearance.wireframe is wireframe
            await pilot.press("escape")
            assert not isinstance(app.screen, HelpScreen)
            await pilot.press("f1")
            assert isinstance(app.screen, HelpScreen)
            await pilot.press("question_mark")
            assert not isinstance(app.screen, HelpScreen)
    run(go())


def _help_lines(app) -> list[str]:
    text = app.screen.query_one("#help-text")
    return [strip.text.rstrip() for strip in
            text.render_lines(Region(0, 0, text.size.width, text.size.height))]


@pytest.mark.parametrize("size", [SIZE, (80, 24)])
def test_help_scrolls_from_the_keyboard_and_cuts_no_label(tmp_path, size):
    async def go():
        app = make_app(tmp_path)
        async with app.run_test(size=size) as pilot:
            await pilot.press("question_mark")
            box = app.screen.query_one("#help")
            await until(pilot, lambda: box.max_scroll_y > 0, what="a help taller than the screen")
            for key in ("down", "j", "pagedown", "space"):
                await pilot.press("home")
                await until(pilot, lambda: box.scroll_y == 0, timeout=5, what="Home: the top")
                await pilot.press(key)
                await until(pilot, lambda: box.scroll_y > 0, timeout=5,
                            what=f"{key} scrolls down")
            before = box.scroll_y
            await pilot.press("k")
            await until(pilot, lambda: box.scroll_y < before, timeout=5, what="k scrolls up")
            await pilot.press("end")
            await until(pilot, lambda: box.scroll_y == box.max_scroll_y, timeout=5,
                        what="End reaches the bottom")
            lines = _help_lines(app)
            for what, does in MOUSE_ACTIONS:  # each label whole, on one line with its text
                assert any(line.strip().startswith(what) for line in lines), what
    run(go())
