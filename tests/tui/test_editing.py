"""Pilot tests: editing flows (issue 14 item 5). Enter applies and moves on, Escape restores
and leaves, space toggles a focused switch, focus is visible, digits typed with no field do
not move the camera unseen, colours have a swatch."""

from textual.color import Color
from textual.widgets import Collapsible, Input, Static, Switch

from cloth_tui.tui.panels import widget_id

from .conftest import SIZE, make_app, notifications, run, sim_scene, until


def _control(app, dotted):
    return app.query_one("#" + widget_id(dotted))


def test_enter_applies_and_moves_to_the_next_field(tmp_path):
    async def go():
        app = make_app(tmp_path)
        async with app.run_test(size=SIZE) as pilot:
            size = _control(app, "cloth.size")
            size.focus()
            size.value = "1.5"
            await pilot.press("enter")
            await until(pilot, lambda: sim_scene(app).cloth.size == 1.5, what="applied")
            assert app.focused is _control(app, "cloth.resolution")
            await pilot.press("tab")  # and on from there, as Tab goes
            assert app.focused is _control(app, "appearance.wireframe")
    run(go())


def test_escape_restores_the_last_good_value_and_leaves(tmp_path):
    async def go():
        app = make_app(tmp_path)
        async with app.run_test(size=SIZE) as pilot:
            field = _control(app, "forces.gravity_strength")
            field.focus()
            await pilot.pause(0.05)
            field.value = ""
            await pilot.press("1", "2", "3")
            assert field.value == "123"
            await pilot.press("escape")
            await pilot.pause(0.1)
            assert app.focused is None
            assert field.value == "9.81" and app.scene.forces.gravity_strength == 9.81
            assert sim_scene(app).forces.gravity_strength == 9.81
    run(go())


def test_space_toggles_a_focused_switch_and_pauses_only_without_focus(tmp_path):
    async def go():
        app = make_app(tmp_path, start_paused=False)
        async with app.run_test(size=SIZE) as pilot:
            wind = _control(app, "forces.wind")
            wind.focus()
            await pilot.press("space")
            await until(pilot, lambda: app.scene.forces.wind, what="wind on")
            assert wind.value is True
            assert not app.sim.paused
            await pilot.press("escape")
            await until(pilot, lambda: app.focused is None, what="focus left")
            await pilot.press("space")  # no control has focus: space pauses
            assert app.sim.paused and app.scene.forces.wind is True
            await pilot.pause(0.1)  # the keys' events finish bubbling before the app closes
    run(go())


def test_focus_is_clearly_visible(tmp_path):
    async def go():
        app = make_app(tmp_path)
        async with app.run_test(size=SIZE) as pilot:
            row = app.query_one("#" + widget_id("forces.wind") + "-row")
            label = row.query_one(".setting-label")
            assert row.rich_style.bgcolor == row.parent.rich_style.bgcolor
            _control(app, "forces.wind").focus()
            await pilot.pause(0.1)
            # the whole row stands out from its group, and its label is bold
            assert row.rich_style.bgcolor != row.parent.rich_style.bgcolor
            assert label.rich_style.bold
    run(go())


def test_digits_with_no_field_focused_do_not_move_the_camera_unseen(tmp_path):
    async def go():
        app = make_app(tmp_path)
        async with app.run_test(size=SIZE) as pilot:
            await pilot.press("0")  # as in typing "0.5" with no field focused
            assert not [c for c in app.renderer.calls if c[0] == "reset_camera"]
            assert any("no field focused" in m for m in notifications(app))
            await pilot.press("full_stop", "5")
            assert any("orbit up" in m for m in notifications(app))  # what `.` did is told
            field = _control(app, "behavior.iterations")
            field.focus()
            field.value = ""
            await pilot.press("7")  # in a field, a digit is just typed
            assert field.value == "7"
            assert sum("no field focused" in m for m in notifications(app)) == 2
    run(go())


def test_colour_fields_show_a_swatch_and_show_constraints_is_in_appearance(tmp_path):
    async def go():
        app = make_app(tmp_path)
        async with app.run_test(size=SIZE) as pilot:
            swatch = app.query_one("#" + widget_id("appearance.cloth_color") + "-swatch",
                                   Static)
            assert swatch.styles.background == Color.parse("#aa2929")
            field = app.query_one("#" + widget_id("appearance.cloth_color"), Input)
            field.focus()
            field.value = "#00ff00"
            await pilot.press("enter")
            await pilot.pause(0.05)
            assert swatch.styles.background == Color.parse("#00ff00")
            field.focus()
            field.value = "green"  # refused: the swatch keeps the last good colour
            await pilot.press("enter")
            await pilot.pause(0.05)
            assert swatch.styles.background == Color.parse("#00ff00")

            appearance = app.query_one("#group-appearance", Collapsible)
            assert appearance.query("#" + widget_id("appearance.show_constraints"))
            assert isinstance(_control(app, "appearance.show_constraints"), Switch)
    run(go())


def test_size_and_resolution_fields_take_a_rectangle_and_refuse_a_bad_one(tmp_path):
    async def go():
        app = make_app(tmp_path)
        async with app.run_test(size=SIZE) as pilot:
            size = _control(app, "cloth.size")
            size.focus()
            size.value = "2, 0.5"
            await pilot.press("enter")
            await until(pilot, lambda: sim_scene(app).cloth.size == [2.0, 0.5],
                        what="a rectangle applied")
            await until(pilot, lambda: (app.sim.sim.model.nx, app.sim.sim.model.nz) == (26, 7),
                        what="its model")
            resolution = _control(app, "cloth.resolution")
            resolution.focus()
            resolution.value = "30, 1"  # a single row: refused, the last good value kept
            await pilot.press("enter")
            await until(pilot, lambda: any("cloth.resolution" in m
                                           for m in notifications(app)), what="a message")
            assert app.scene.cloth.resolution == 26 and resolution.value == "26"
            resolution.focus()
            resolution.value = "[30, 8]"
            await pilot.press("enter")
            await until(pilot, lambda: (app.sim.sim.model.nx, app.sim.sim.model.nz) == (30, 8),
                        what="the given counts")
            assert size.value == "2, 0.5"
    run(go())
