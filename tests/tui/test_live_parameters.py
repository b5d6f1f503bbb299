"""Editing a force, friction or damping value in the running app: the simulation's step
takes the value as it runs (sim/params.py), keeping its substeps, kernel choice and guard,
and the UI thread builds no model for it."""

import dataclasses
import threading

import pytest

from cloth_tui.scene import Scene
from cloth_tui.sim.model import ClothModel
from cloth_tui.tui.panels import ObjectsPanel, widget_id

from .conftest import SIZE, make_app, notifications, run, sim_scene, until

EDITS = [("forces.wind_strength", "5", 5.0), ("forces.gravity_strength", "4", 4.0),
         ("scene.friction", "0.3", 0.3), ("behavior.damping", "0.1", 0.1)]


def test_parameter_edits_keep_the_run_and_build_no_model_on_the_ui_thread(tmp_path,
                                                                        monkeypatch):
    ui_thread = threading.get_ident()
    built_on_ui: list[str] = []
    init = ClothModel.__init__

    def watched(self, *args, **kwargs):
        if threading.get_ident() == ui_thread:
            built_on_ui.append("ClothModel")
        init(self, *args, **kwargs)

    scene = Scene().with_values({"cloth.resolution": 12, "forces.wind": True,
                                 "forces.wind_strength": 3.0, "scene.object": "sphere"})

    async def go():
        app = make_app(tmp_path, scene)
        async with app.run_test(size=SIZE) as pilot:
            await until(pilot, lambda: app.sim is not None, what="the simulation")

            def as_after_a_hard_frame(sim):
                sim.control.substeps = 7   # the adaptive controller's count
                sim._guard_level = 1       # the guard retrying at twice that
                sim.recoveries = 1
                sim._build_step()
            app.sim.submit(as_after_a_hard_frame)
            await until(pilot, lambda: app.sim.sim.step.substeps == 14, what="the guard")
            sim = app.sim.sim
            step, kernels = sim.step, sim.step.solver.projection.kernels
            control = dataclasses.asdict(sim.control)
            monkeypatch.setattr(ClothModel, "__init__", watched)
            for dotted, text, value in EDITS:
                field = app.query_one("#" + widget_id(dotted))
                field.focus()
                field.value = text
                await pilot.press("enter")
                await until(pilot, lambda: sim_scene(app).get(dotted) == value, what=dotted)
                assert app.scene.get(dotted) == value
            assert built_on_ui == []
            assert sim.step is step and sim.step.substeps == 14
            assert sim.step.solver.projection.kernels is kernels
            assert dataclasses.asdict(sim.control) == control
            assert (sim._guard_level, sim.recoveries) == (1, 1)
            p = sim.step.params
            assert (p.wind_speed, p.gravity, p.friction, p.damping) == (5.0, 4.0, 0.3, 0.1)

            # a refused value returns to the field that asked: it shows the last good one
            field = app.query_one("#" + widget_id("forces.wind_strength"))
            field.focus()
            field.value = "-2"
            await pilot.press("enter")
            await pilot.pause(0.1)
            assert any("forces.wind_strength = -2" in n for n in notifications(app))
            assert field.value == "5" and app.scene.forces.wind_strength == 5.0
            assert app.focused is field
    run(go())


def test_edits_that_move_nothing_held_build_no_model_on_the_ui_thread(tmp_path, monkeypatch):
    """Wind switched on (a new step), a colour, the sheet's mass: nothing held or in the way
    moves, so there is nothing to check for held particles in objects."""
    ui_thread = threading.get_ident()
    built_on_ui: list[str] = []
    init = ClothModel.__init__

    def watched(self, *args, **kwargs):
        if threading.get_ident() == ui_thread:
            built_on_ui.append("ClothModel")
        init(self, *args, **kwargs)

    async def go():
        app = make_app(tmp_path, Scene().with_value("cloth.resolution", 12))
        async with app.run_test(size=SIZE) as pilot:
            await until(pilot, lambda: app.sim is not None, what="the simulation")
            monkeypatch.setattr(ClothModel, "__init__", watched)
            for dotted, value in (("forces.wind", True), ("appearance.cloth_color", "#112233"),
                                  ("cloth.mass", 0.5)):
                assert app.set_value(dotted, value)
                await until(pilot, lambda: sim_scene(app).get(dotted) == value, what=dotted)
            assert built_on_ui == []
            assert "wind" in app.sim.sim.step.names
            assert float(app.sim.sim.model.mass.sum()) == pytest.approx(0.5)
    run(go())


def test_an_objects_friction_edit_keeps_the_step_and_builds_no_model_on_the_ui_thread(
        tmp_path, monkeypatch):
    ui_thread = threading.get_ident()
    built_on_ui: list[str] = []
    init = ClothModel.__init__

    def watched(self, *args, **kwargs):
        if threading.get_ident() == ui_thread:
            built_on_ui.append("ClothModel")
        init(self, *args, **kwargs)

    sphere = {"type": "sphere", "center": [0.0, -0.1, 0.0], "radius": 0.3}
    scene = Scene().with_value("cloth.resolution", 12).with_objects([sphere])

    async def go():
        app = make_app(tmp_path, scene)
        async with app.run_test(size=SIZE) as pilot:
            await until(pilot, lambda: app.sim is not None, what="the simulation")
            step = app.sim.sim.step
            monkeypatch.setattr(ClothModel, "__init__", watched)
            tables = [dataclasses.asdict(o) for o in app.scene.objects]
            tables[0]["friction"] = 0.2
            app.post_message(ObjectsPanel.Changed(tables))
            await until(pilot, lambda: sim_scene(app).objects[0].friction == 0.2,
                        what="the object's friction")
            assert built_on_ui == []
            assert app.sim.sim.step is step
            assert [c.friction for c in step.colliders] == [0.9, 0.2]  # the floor's, its own
    run(go())


def test_an_edit_that_may_move_a_held_particle_is_checked_once_on_the_ui_thread(
        tmp_path, monkeypatch):
    """Moving an object is checked for held particles in its skin where it is asked for,
    and the simulation thread, which is handed the checked scene, does not check again."""
    from cloth_tui.sim.collision import held_contacts

    checks: list[str] = []
    ui_thread = threading.get_ident()

    def counted(check):
        def run_check(*args):
            checks.append("ui" if threading.get_ident() == ui_thread else "sim")
            return check(*args)
        return run_check

    sphere = {"type": "sphere", "center": [0.0, -0.1, 0.0], "radius": 0.3}
    scene = Scene().with_value("cloth.resolution", 12).with_objects([sphere])

    async def go():
        app = make_app(tmp_path, scene)
        async with app.run_test(size=SIZE) as pilot:
            await until(pilot, lambda: app.sim is not None, what="the simulation")
            # every check, the app's (check_start) and the simulation's, runs this one
            monkeypatch.setattr(held_contacts, "check_held_particles",
                                counted(held_contacts.check_held_particles))
            app.post_message(ObjectsPanel.Changed([{**sphere, "center": [0.1, -0.1, 0.0]}]))
            await until(pilot, lambda: sim_scene(app).objects[0].center[0] == 0.1,
                        what="the object moved")
            assert checks == ["ui"]
    run(go())
