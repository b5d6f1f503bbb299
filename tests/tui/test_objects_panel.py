"""Pilot test: the scene's [[objects]] are listed in the Scene group, and can be edited, added
and removed there; a refused edit is told and the field shows the last good value."""

from textual.widgets import Button, Collapsible, Input, Select

from cloth_tui.scene_files import load
from cloth_tui.tui.panels import widget_id

from .conftest import SIZE, make_app, notifications, run, sim_scene, until

HAND_WRITTEN = """
[[objects]]
type = "sphere"
center = [0.1, -0.2, 0.0]
radius = 0.2

[[objects]]
type = "box"
center = [0.0, -0.4, 0.0]
size = [0.3, 0.1, 0.3]
"""


def test_objects_are_listed_edited_added_and_removed(tmp_path):
    path = tmp_path / "two.toml"
    path.write_text(HAND_WRITTEN, encoding="utf-8")
    scene = load(path)

    async def go():
        app = make_app(tmp_path, scene)
        async with app.run_test(size=SIZE) as pilot:
            app.query_one("#group-scene", Collapsible).collapsed = False
            titles = [c.title for c in app.query("#objects Collapsible")]
            assert titles == ["1. sphere at (0.1, -0.2, 0)", "2. box at (0, -0.4, 0)"]
            radius = app.query_one("#" + widget_id("objects.0.radius"), Input)
            assert radius.value == "0.2"

            # edit: Enter applies to the app, the simulation and the renderer
            radius.focus()
            radius.value = "0.3"
            await pilot.press("enter")
            await until(pilot, lambda: sim_scene(app).objects[0].radius == 0.3, what="edit")
            await until(pilot, lambda: app.renderer.scene.objects[0].radius == 0.3,
                        what="the edit in the renderer")
            assert app.focused is not radius  # on to the next field

            # refused: told, and the last good value comes back
            radius.focus()
            radius.value = "-1"
            await pilot.press("enter")
            await pilot.pause(0.05)
            assert radius.value == "0.3" and app.scene.objects[0].radius == 0.3
            assert any("objects[0].radius" in m for m in notifications(app))

            # add a capsule
            app.query_one("#add-object-type", Select).value = "capsule"
            app.query_one("#add-object", Button).press()
            await until(pilot, lambda: len(sim_scene(app).objects) == 3, what="added")
            assert app.scene.objects[2].type == "capsule"
            await until(pilot, lambda: len(app.query("#objects Collapsible")) == 3,
                        what="new rows")
            # a mesh needs its file: refused with the scene's message, nothing added
            app.query_one("#add-object-type", Select).value = "mesh"
            app.query_one("#add-object", Button).press()
            await until(pilot, lambda: any("mesh needs" in m for m in notifications(app)))
            assert len(app.scene.objects) == 3

            # remove the first: the box is first now, in the panel too
            app.query_one("#remove-object-0", Button).press()
            await until(pilot, lambda: len(sim_scene(app).objects) == 2, what="removed")
            assert [o.type for o in app.scene.objects] == ["box", "capsule"]
            await until(pilot, lambda: len(app.query("#objects Collapsible")) == 2)
            titles = [c.title for c in app.query("#objects Collapsible")]
            assert titles[0].startswith("1. box")
            assert app.query_one("#" + widget_id("objects.0.type"), Select).value == "box"
    run(go())


def test_focus_stays_in_the_list_after_add_and_remove(tmp_path):
    async def go():
        app = make_app(tmp_path)
        async with app.run_test(size=SIZE) as pilot:
            app.query_one("#group-scene", Collapsible).collapsed = False
            height = app.scene.cloth.height
            panel = app.query_one("#objects")
            app.query_one("#add-object", Button).focus()
            await pilot.press("enter")
            await until(pilot, lambda: len(app.query("#objects Collapsible")) == 1,
                        what="the new object's rows")
            await pilot.pause(0.1)
            assert app.focused is app.query_one("#add-object", Button)

            app.query_one("#object-0", Collapsible).collapsed = False
            await pilot.pause(0.1)
            app.query_one("#remove-object-0", Button).focus()
            await pilot.press("enter")
            await until(pilot, lambda: not app.query("#objects Collapsible"), what="removed")
            await pilot.pause(0.1)
            assert app.focused is not None and panel in app.focused.ancestors_with_self
            await pilot.press("5")  # no field took the focus: nothing is edited
            await pilot.pause(0.1)
            assert app.scene.cloth.height == height
    run(go())
