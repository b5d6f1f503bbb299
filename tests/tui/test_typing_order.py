"""Pilot tests: keys reach a field in the order typed, however many arrive at once. A terminal
read under load hands the app several keys in one go (the driver sends them together); these
tests send such bursts while the simulation runs with the app's GIL switch interval, and the
field must end as if each key had been applied before the next."""

import sys
import unicodedata

import pytest
from textual import events
from textual.keys import _character_to_key, _get_unicode_name_from_key

from cloth_tui.scene import Scene
from cloth_tui.scene_files import load
from cloth_tui.tui.process import GIL_SWITCH_INTERVAL_S
from cloth_tui.tui.panels import widget_id

from .conftest import SIZE, make_app, run, sim_scene, until


def _key_event(key: str) -> events.Key:
    """The event the driver makes for one key, as Textual's Pilot builds it."""
    if len(key) == 1 and not key.isalnum():
        key = _character_to_key(key)
    try:
        char = unicodedata.lookup(_get_unicode_name_from_key(key))
    except KeyError:
        char = key if len(key) == 1 else None
    return events.Key(key, char)


def burst(app, *keys: str) -> None:
    """Hand the app these keys at once, as one read of a busy terminal does."""
    for key in keys:
        event = _key_event(key)
        event.set_sender(app)
        app._driver.send_message(event)


@pytest.fixture
def busy_gil():
    """The app's switch interval, as `run_app` sets it, for the simulation thread beside."""
    before = sys.getswitchinterval()
    sys.setswitchinterval(GIL_SWITCH_INTERVAL_S)
    yield
    sys.setswitchinterval(before)


def _busy_app(tmp_path, scene=None):
    scene = scene or Scene()
    scene = scene.with_value("cloth.resolution", 48)
    return make_app(tmp_path, scene, start_paused=False)


def _field(app, dotted):
    return app.query_one("#" + widget_id(dotted))


async def _focused_with(pilot, app, dotted, text):
    field = _field(app, dotted)
    field.focus()
    field.value = text
    field.cursor_position = len(text)
    await until(pilot, lambda: app.focused is field, what="focus")
    await until(pilot, lambda: app.sim.latest is not None and app.sim.latest.frame > 2,
                what="simulation running")
    return field


async def _shows(pilot, field, text):
    try:
        await until(pilot, lambda: field.value == text, timeout=5, what=repr(text))
    except AssertionError:
        raise AssertionError(f"the field shows {field.value!r}, not {text!r}") from None


def test_edit_keys_and_characters_apply_in_the_order_typed(tmp_path, busy_gil):
    async def go():
        app = _busy_app(tmp_path)
        async with app.run_test(size=SIZE) as pilot:
            field = await _focused_with(pilot, app, "forces.gravity_strength", "4321")
            burst(app, "backspace", "7")
            await _shows(pilot, field, "4327")
            burst(app, "home", "1", "end", "0", "left", "left", "delete", ".")
            await _shows(pilot, field, "1432.0")
            burst(app, "end", *["backspace"] * 8, "2", ".", "5", "home", "shift+end", "9")
            await _shows(pilot, field, "9")
    run(go())


def test_enter_then_typing_goes_to_the_next_field(tmp_path, busy_gil):
    """Enter applies the value and moves on; what is typed next belongs to the next field."""
    async def go():
        app = _busy_app(tmp_path)
        async with app.run_test(size=SIZE) as pilot:
            size = await _focused_with(pilot, app, "cloth.size", "1")
            resolution = _field(app, "cloth.resolution")
            burst(app, "backspace", "2", "enter", *["backspace"] * 4, "3", "2", "tab")
            await _shows(pilot, resolution, "32")
            await until(pilot, lambda: app.scene.cloth.resolution == 32, timeout=10,
                        what="resolution 32 applied when Tab left the field")
            assert app.scene.cloth.size == 2.0 and size.value == "2"
            assert app.focused is _field(app, "appearance.wireframe")
    run(go())


def test_an_object_radius_typed_over_takes_the_new_value(tmp_path, busy_gil):
    """The case a user met: Backspace ×5, `-1`… gave "radius = '-'"; here `0.31` Enter."""
    path = tmp_path / "ball.toml"
    path.write_text('[[objects]]\ntype = "sphere"\ncenter = [0, -0.3, 0]\nradius = 0.25\n',
                    encoding="utf-8")

    async def go():
        app = _busy_app(tmp_path, load(path))
        async with app.run_test(size=SIZE) as pilot:
            app.query_one("#group-scene").collapsed = False
            await _focused_with(pilot, app, "objects.0.radius", "0.25")
            burst(app, *["backspace"] * 5, "0", ".", "3", "1", "enter")
            await until(pilot, lambda: sim_scene(app).objects[0].radius == 0.31, timeout=10,
                        what="radius 0.31")
    run(go())


def test_tab_then_typing_goes_to_the_field_tab_reached(tmp_path, busy_gil):
    """From no focus, the first Tab reaches the controls' scroll area, the second the first
    field: what is typed after them is that field's."""
    async def go():
        app = _busy_app(tmp_path)
        async with app.run_test(size=SIZE) as pilot:
            await until(pilot, lambda: app.sim.latest is not None and app.sim.latest.frame > 2,
                        what="simulation running")
            assert app.focused is None
            burst(app, "tab", "tab", "end", "backspace", "3")
            await _shows(pilot, _field(app, "cloth.size"), "3")
            assert app.focused is _field(app, "cloth.size")
    run(go())
