"""The app's notices show user text literally: control characters in file names, keys and
values are escaped, and brackets are not read as markup (issue 19)."""

import unicodedata

from textual.widgets import Input

from cloth_tui.scene import Scene
from cloth_tui.scene_files import load, save
from cloth_tui.tui.panels import widget_id

from .conftest import SIZE, make_app, notifications, run, until

UNSAFE = {"Cc", "Cf", "Zl", "Zp", "Cs"}


def shown_safely(text: str) -> bool:
    return not any(unicodedata.category(c) in UNSAFE for c in text)


def test_notices_escape_file_names_and_a_scene_named_with_a_newline_saves(tmp_path):
    hostile = "caps\x1b]0;owned\x07\x1b[31m\nline"
    scene_file = save(Scene().with_value("cloth.mass", 0.3), tmp_path / "my\nscene.toml")
    scene = load(scene_file)
    assert scene.name == "my\nscene"

    async def go():
        app = make_app(tmp_path, scene)
        app.captures_dir = tmp_path / hostile
        async with app.run_test(size=SIZE) as pilot:
            await pilot.press("s")
            await pilot.pause()
            saved = list((tmp_path / hostile).glob("scene-*.toml"))
            assert len(saved) == 1 and load(saved[0]) == scene
            told = [m for m in notifications(app) if "Scene saved" in m]
            assert told and all(shown_safely(m) for m in told)
            assert "\\x1b]0;owned\\x07" in told[0]
    run(go())


def test_a_refused_value_is_shown_literally_even_when_it_looks_like_markup(tmp_path):
    async def go():
        app = make_app(tmp_path)
        async with app.run_test(size=SIZE) as pilot:
            field = app.query_one("#" + widget_id("appearance.cloth_color"), Input)
            field.focus()
            field.value = "[/bold]\x1b[2J[red]"
            await pilot.press("enter")
            await pilot.pause()
            assert app.is_running
            refused = [n for n in app._notifications if "cloth_color" in n.message]
            assert refused and all(shown_safely(n.message) for n in refused)
            assert all(not n.markup for n in refused)
    run(go())


def test_a_change_that_puts_held_particles_inside_an_object_is_refused_not_fatal(tmp_path):
    """A box the pinned corners of a shrunk sheet start in: refused with the reason before the
    simulation thread sees it (it raised there and the thread died)."""
    scene = Scene().with_values({"scene.object": "box", "cloth.height": 0.0})

    async def go():
        app = make_app(tmp_path, scene)
        async with app.run_test(size=SIZE) as pilot:
            assert not app.set_value("cloth.size", 0.4)
            await pilot.pause()
            assert any("encloses a held particle" in m for m in notifications(app))
            assert app.scene.cloth.size == 1.0
            await pilot.pause(0.3)
            assert app.sim.error is None and app.sim.sim.scene.cloth.size == 1.0
    run(go())


def test_an_object_added_over_a_pinned_corner_is_refused_not_fatal(tmp_path):
    """The Scene group's objects go through the same check as a setting: a sphere edited onto
    a pinned corner is refused with the reason, and the simulation thread lives on."""
    from textual.widgets import Collapsible

    scene = Scene().with_values({"scene.object": "none"})
    scene = scene.with_objects([{"type": "sphere", "center": [2.0, 0.0, 0.0], "radius": 0.2}])
    corner = scene.cloth.size / 2

    async def go():
        app = make_app(tmp_path, scene)
        async with app.run_test(size=SIZE) as pilot:
            app.query_one("#group-scene", Collapsible).collapsed = False
            center = app.query_one("#" + widget_id("objects.0.center"), Input)
            center.focus()
            center.value = f"{corner}, {scene.cloth.height}, {corner}"
            await pilot.press("enter")
            await until(pilot, lambda: any("encloses a held particle" in m
                                           for m in notifications(app)), what="refusal")
            assert list(app.scene.objects[0].center) == [2.0, 0.0, 0.0]
            await pilot.pause(0.3)
            assert app.sim.error is None
            assert list(app.sim.sim.scene.objects[0].center) == [2.0, 0.0, 0.0]
    run(go())
