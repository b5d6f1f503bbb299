"""The step's parameters (sim/params.py): a change of a value the stages read is taken by
the running step, with its substeps, kernels and guard, and gives the run a step built for
the new value would have."""

import dataclasses

import numpy as np
import pytest

from cloth_tui.sim.params import PARAMETER_KEYS, StepParams, same_structure
from cloth_tui.sim.run.runner import Simulation

from .helpers import run, scene

SMALL = {"cloth.resolution": 8}
FRAMES = 30

# (the scene's other settings, the key, its new value): every parameter, in a scene where
# its stage runs
EDITS = [
    ({}, "forces.gravity_strength", 4.0),
    ({"forces.wind": True, "forces.wind_strength": 3.0}, "forces.wind_strength", 8.0),
    ({"forces.wind": True}, "forces.wind_direction", [1.0, 0.0, 0.5]),
    ({"forces.wind": True}, "forces.wind_mode", "gusty"),
    ({"forces.custom": "vortex"}, "forces.custom_strength", 4.0),
    ({"forces.custom": "black_hole"}, "forces.custom_rate", 2.0),
    ({"forces.rain": True}, "forces.rain_strength", 0.03),
    ({"forces.rain": True}, "forces.rain_rate", 60.0),
    ({"scene.object": "sphere", "cloth.pinned": "none"}, "scene.friction", 0.05),
    ({}, "behavior.damping", 0.2),
    ({"behavior.solver": "xpbd", "behavior.compliance": 1e-3}, "behavior.compliance", 1e-5),
    ({}, "behavior.iterations", 9),
    ({"cloth.pinned": "none"}, "behavior.max_speed", 1.0),
    ({"behavior.solver": "springs"}, "behavior.stiffness", 800.0),
    ({"behavior.solver": "springs"}, "behavior.spring_damping", 0.1),
    ({"forces.wind": True}, "cloth.mass", 0.05),
]
DENIM = {"behavior.solver": "xpbd", "material.preset": "denim"}
MATERIAL_EDITS = [(DENIM, "material.stretch", 200.0), (DENIM, "material.shear", 5.0),
                  (DENIM, "material.bending", 1e-4), (DENIM, "material.damping", 2.0),
                  (DENIM, "material.areal_density", 0.6),
                  ({**DENIM, "behavior.solver": "lbfgs"}, "material.damping", 2.0)]


def test_every_parameter_key_is_edited_below():
    assert {key for _, key, _ in EDITS} == set(PARAMETER_KEYS)


@pytest.mark.parametrize("settings, key, value", EDITS + MATERIAL_EDITS,
                         ids=[e[1] for e in EDITS + MATERIAL_EDITS])
def test_an_edited_parameter_runs_as_a_step_built_for_it(settings, key, value):
    before = scene(**{k.replace(".", "__"): v for k, v in {**SMALL, **settings}.items()})
    assert_taken_live(before, before.with_value(key, value))


def test_an_objects_friction_is_taken_live():
    before = scene(cloth__resolution=8, cloth__pinned="none", scene__floor=False)
    sphere = {"type": "sphere", "center": [0.0, -0.1, 0.0], "radius": 0.3}
    assert_taken_live(before.with_objects([{**sphere, "friction": 0.9}]),
                      before.with_objects([{**sphere, "friction": 0.02}]))


def assert_taken_live(before, after):
    """A run edited from `before` to `after` at its start is the run built for `after`, and
    not the one built for `before`."""
    assert same_structure(before, after)
    edited = Simulation(before)
    step = edited.step
    assert edited.set_scene(after) is False
    assert edited.step is step  # not rebuilt
    x_edited = run(edited, FRAMES).state.x
    x_built = run(Simulation(after), FRAMES).state.x
    x_old = run(Simulation(before), FRAMES).state.x
    np.testing.assert_array_equal(x_edited, x_built)
    assert not np.array_equal(x_edited, x_old)  # the value matters to this run


def test_an_edit_keeps_the_substeps_the_kernel_choice_and_the_guard():
    sim = run(Simulation(scene(cloth__resolution=12, forces__wind=True,
                               forces__wind_strength=3.0)), 5)
    sim.control.substeps = 7  # as the adaptive controller leaves it
    sim._guard_level = 1      # as a recovered frame leaves the guard
    sim.recoveries = 1
    sim._build_step()
    step, kernels = sim.step, sim.step.solver.projection.kernels
    control = dataclasses.asdict(sim.control)
    assert sim.set_scene(sim.scene.with_value("forces.wind_strength", 5.0)) is False
    assert sim.step is step and sim.step.substeps == 14
    assert sim.step.solver.projection.kernels is kernels
    assert dataclasses.asdict(sim.control) == control
    assert (sim._guard_level, sim.recoveries) == (1, 1)
    assert sim.step.params.wind_speed == 5.0
    run(sim, 1)
    assert sim.state.is_finite()


def test_an_effect_switched_on_or_off_rebuilds_the_step():
    sim = Simulation(scene(cloth__resolution=8, forces__wind=True, forces__wind_strength=3.0))
    step = sim.step
    sim.set_scene(sim.scene.with_value("forces.wind_strength", 0.0))
    assert sim.step is not step and "wind" not in sim.step.names


def test_a_material_gaining_bending_rebuilds_the_step():
    sim = Simulation(scene(cloth__resolution=8, behavior__solver="xpbd",
                           material__preset="denim", material__bending=0.0))
    step = sim.step
    sim.set_scene(sim.scene.with_value("material.bending", 1e-4))
    assert sim.step is not step and sim.model.fabric.num_stencils > 0


def test_a_sheet_that_tears_by_strength_rebuilds_for_its_material_numbers():
    """Its tearing stage and the substeps' tolerance are made from the strength and the
    stretch."""
    base = scene(behavior__solver="xpbd", behavior__tear=True, material__preset="denim",
                 material__tear_strength=300.0)
    assert not same_structure(base, base.with_value("material.tear_strength", 400.0))
    assert not same_structure(base, base.with_value("material.stretch", 900.0))
    assert same_structure(base, base.with_value("forces.gravity_strength", 5.0))
    no_tear = base.with_value("behavior.tear", False)
    assert same_structure(no_tear, no_tear.with_value("material.stretch", 900.0))


@pytest.mark.parametrize("key, a, b, same", [
    ("forces.wind_strength", 3.0, 5.0, True),
    ("forces.wind_strength", 0.0, 5.0, False),    # a wind stage appears
    ("forces.gravity_strength", 9.81, 0.0, False),
    ("behavior.damping", 0.0, 0.5, True),
    ("scene.friction", 0.0, 1.0, True),
    ("cloth.resolution", 8, 9, False),            # topology
    ("behavior.substeps", 4, 5, False),
    ("forces.wind", False, True, False),
])
def test_structure(key, a, b, same):
    base = scene()
    assert same_structure(base.with_value(key, a), base.with_value(key, b)) is same


def test_params_assign_the_scene_values():
    s = scene(forces__wind_direction=[0.0, 3.0, 4.0], scene__friction=0.25,
              behavior__iterations=7)
    p = StepParams()
    p.assign(s)
    assert p == StepParams.of(s)
    assert p.wind_direction == pytest.approx((0.0, 0.6, 0.8))
    assert (p.friction, p.iterations) == (0.25, 7)


def test_the_defaults_are_the_default_scenes():
    assert StepParams() == StepParams.of(scene())
