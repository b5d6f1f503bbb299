"""Contacts hold in a crevice between two objects: friction along one object's tangent must
not leave a particle inside the other (issue 19's fuzzer: 2.5 cm deep in a sphere wedged
against a capsule, at thickness 1e-9)."""

import math

from hypothesis import HealthCheck, given, settings
from hypothesis import strategies as st

from cloth_tui.scene import SceneObject
from cloth_tui.sim.run.runner import Simulation

from ..helpers import run, scene

SLACK = 0.01  # m beyond scene.thickness, as the fuzzer allows


@settings(max_examples=12, deadline=None, suppress_health_check=[HealthCheck.too_slow])
@given(gravity=st.floats(math.log(100.0), math.log(1e4)).map(lambda v: min(1e4, math.exp(v))),
       friction=st.floats(0.3, 1.0), thickness=st.sampled_from([0.0, 1e-9, 0.005]),
       radius=st.floats(0.15, 0.3), dx=st.floats(-0.2, 0.2),
       second=st.sampled_from(["capsule", "box", "sphere"]))
def test_a_sheet_pressed_into_a_crevice_stays_out_of_both_objects(gravity, friction, thickness,
                                                                  radius, dx, second):
    s = scene(cloth__resolution=16, cloth__pinned="one_edge", forces__gravity_strength=gravity,
              scene__friction=friction, scene__thickness=thickness,
              behavior__frame_rate=1.0, behavior__substeps=100, behavior__adaptive=False)
    other = SceneObject(type=second, center=[dx, -0.1, 0.0], radius=0.15)
    s.objects = [other, SceneObject(type="sphere", center=[0.0, -0.25, 0.0], radius=radius)]
    sim = run(Simulation(s), 3)
    st_ = sim.stats()
    assert st_.finite and st_.penetration <= thickness + SLACK, st_.penetration
