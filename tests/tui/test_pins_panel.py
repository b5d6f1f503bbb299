"""Pilot tests: the scene's [[pins]] are listed in the Scene group and can be edited, added
and removed there (a refused edit is told and the last good value kept); Ctrl+drag pins the
grabbed particle where it is let go, and `r` restores the scene's pins."""

import numpy as np
from textual.widgets import Button, Collapsible, Input

from cloth_tui import scene_files as sf
from cloth_tui.scene import Scene
from cloth_tui.tui.panels import widget_id

from .conftest import SIZE, make_app, notifications, run, sim_scene, until

GROUPS = "pins=[{rows=[0,0], cols=[0,-1]}, {at=[[-1,-1]], keys=[[0,0,0,0],[1,0,0.1,0]]}]"


def pinned_scene() -> Scene:
    return sf.apply_overrides(Scene(), ["cloth.pinned=none", GROUPS])


def field(app, dotted):
    return app.query_one("#" + widget_id(dotted), Input)


def test_pin_groups_are_listed_edited_added_and_removed(tmp_path):
    async def go():
        app = make_app(tmp_path, pinned_scene())
        async with app.run_test(size=SIZE) as pilot:
            app.query_one("#group-scene", Collapsible).collapsed = False
            titles = [c.title for c in app.query("#pins Collapsible")]
            assert titles == ["1. rows 0…0, cols 0…-1", "2. at [-1, -1], moving"]
            assert field(app, "pins.0.cols").value == "0, -1"
            assert field(app, "pins.1.keys").value == "[[0, 0, 0, 0], [1, 0, 0.1, 0]]"

            # edit: Enter applies to the app and the simulation
            offset = field(app, "pins.0.offset")
            offset.focus()
            offset.value = "0, 0.05, 0"
            await pilot.press("enter")
            await until(pilot, lambda: sim_scene(app).pins[0].offset == [0, 0.05, 0],
                        what="edit")
            await until(pilot, lambda: np.allclose(
                app.sim.latest.positions[0], app.sim.latest.model.rest_positions[0]
                + [0, 0.05, 0]), what="the held row raised")

            # refused: a range off the sheet is told and the field shows its last good value
            rows = field(app, "pins.0.rows")
            rows.focus()
            rows.value = "0, 99"
            await pilot.press("enter")
            await until(pilot, lambda: any("pins[0].rows = [0, 99] is outside the sheet" in m
                                           for m in notifications(app)))
            assert rows.value == "0, 0" and app.scene.pins[0].rows == [0, 0]
            # refused by the simulation's check: two groups holding a particle differently
            keys = field(app, "pins.1.keys")
            keys.focus()
            keys.value = ""
            await pilot.press("enter")  # keys emptied: [-1, -1] held in place
            await until(pilot, lambda: sim_scene(app).pins[1].keys == [], what="keys cleared")
            at = field(app, "pins.1.at")
            at.focus()
            at.value = "[[0, 3]]"
            await pilot.press("enter")  # [0, 3] is in pins[0] too, which raises it
            await until(pilot, lambda: any("both hold particle [0, 3]" in m
                                           for m in notifications(app)))
            assert app.scene.pins[1].at == [[-1, -1]] and at.value == "[[-1, -1]]"

            # add: a group on [0, 0], which pins[0] holds raised: refused, nothing added
            app.query_one("#add-pins", Button).press()
            await until(pilot, lambda: any("both hold particle [0, 0]" in m
                                           for m in notifications(app)))
            assert len(app.scene.pins) == 2
            # remove the first, then add
            app.query_one("#remove-pins-0", Button).press()
            await until(pilot, lambda: len(sim_scene(app).pins) == 1, what="removed")
            await until(pilot, lambda: len(app.query("#pins Collapsible")) == 1)
            app.query_one("#add-pins", Button).press()
            await until(pilot, lambda: len(sim_scene(app).pins) == 2, what="added")
            assert [g.at for g in app.scene.pins] == [[[-1, -1]], [[0, 0]]]
            await until(pilot, lambda: [c.title for c in app.query("#pins Collapsible")]
                        == ["1. at [-1, -1]", "2. at [0, 0]"])
    run(go())


def test_ctrl_drag_pins_the_particle_where_it_is_let_go_and_r_restores(tmp_path):
    async def go():
        app = make_app(tmp_path)
        async with app.run_test(size=SIZE) as pilot:
            await until(pilot, lambda: app.preview.frames_shown > 0)
            wd = app.preview.size.width
            await pilot.mouse_down("#preview", offset=(wd // 2, 14), control=True)
            grabbed = app._grabbed
            assert grabbed is not None and grabbed not in app.sim.latest.model.pinned
            y0 = app.sim.latest.positions[grabbed][1]
            await pilot.hover("#preview", offset=(wd // 2, 10))
            await until(pilot, lambda: app.sim.latest.positions[grabbed][1] > y0 + 0.01)
            await pilot.mouse_up("#preview", offset=(wd // 2, 10), control=True)
            await until(pilot, lambda: grabbed in app.sim.latest.model.pinned, what="pinned")
            await until(pilot, lambda: any("r restores the scene's pins" in m
                                           for m in notifications(app)))
            held = app.sim.latest.positions[grabbed].copy()
            assert held[1] > y0 + 0.01
            await pilot.press("space")  # run: the pinned particle stays where it was let go
            await until(pilot, lambda: app.sim.latest.frame > 10, what="frames")
            assert np.allclose(app.sim.latest.positions[grabbed], held)
            await pilot.press("r")
            await until(pilot, lambda: grabbed not in app.sim.latest.model.pinned,
                        what="the scene's pins back")

            # p pins the particle under the pointer, where it is (paused: it stays under it)
            await pilot.press("space")
            await pilot.pause(0.2)
            target = app.renderer.pick(*app.preview.target)
            assert target is not None and target not in app.sim.latest.model.pinned
            await pilot.press("p")
            await until(pilot, lambda: target in app.sim.latest.model.pinned,
                        what=f"p pinned {target}: {notifications(app)}")
            await pilot.press("r")
            await until(pilot, lambda: target not in app.sim.latest.model.pinned)

            # a plain drag pins nothing
            await pilot.mouse_down("#preview", offset=(wd // 2, 14))
            other = app._grabbed
            await pilot.mouse_up("#preview", offset=(wd // 2, 14))
            await pilot.pause(0.2)
            assert other not in app.sim.latest.model.pinned
    run(go())


def test_s_saves_the_pin_groups_and_they_load_back(tmp_path):
    async def go():
        app = make_app(tmp_path, pinned_scene())
        async with app.run_test(size=SIZE) as pilot:
            await pilot.press("s")
            await until(pilot, lambda: any("Scene saved" in m for m in notifications(app)))
            (path,) = (tmp_path / "caps").glob("scene*.toml")
            loaded = sf.load(path)
            assert loaded.pins == pinned_scene().pins and loaded == app.scene
    run(go())
