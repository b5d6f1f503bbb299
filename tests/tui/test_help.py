"""Pilot test: `?` and F1 open the help screen, which lists every app key (read from the
bindings) and the mouse actions, by group; Escape closes it."""

from textual.binding import Binding

from cloth_tui.tui.bindings import APP_BINDINGS, KEY_GROUPS, MOUSE_ACTIONS
from cloth_tui.tui.help import HelpScreen, help_groups, key_text
from cloth_tui.tui.panels import SettingField

from .conftest import SIZE, make_app, run


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
