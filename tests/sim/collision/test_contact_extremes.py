"""Contacts hold at the extremes issue 19's fuzzer found: extreme rain on a sheet over objects
that meet the floor, and a free sheet straddling a two-sided plane."""

import math

from hypothesis import HealthCheck, given, settings
from hypothesis import strategies as st

from cloth_tui.scene import SceneObject
from cloth_tui.sim.run.runner import Simulation

from ..helpers import run, scene

SLACK = 0.01  # m beyond scene.thickness, as the fuzzer allows


def log_uniform(lo: float, hi: float):
    # clamped: exp(log(hi)) may round a hair above hi, which the key's range refuses
    return st.floats(math.log(lo), math.log(hi)).map(lambda v: min(hi, max(lo, math.exp(v))))


@settings(max_examples=10, deadline=None, suppress_health_check=[HealthCheck.too_slow])
@given(strength=log_uniform(0.05, 10.0), rate=log_uniform(100.0, 1e5),
       thickness=st.sampled_from([0.005, 0.05]), obj=st.sampled_from(["sphere", "box", "capsule"]),
       seed=st.integers(0, 2**32))
def test_extreme_rain_on_objects_that_meet_the_floor_stays_out_of_both(strength, rate,
                                                                      thickness, obj, seed):
    # each object reaches down into the floor's skin, so drops drive particles into the crevice
    low = {"sphere": dict(center=[0.0, -0.25, 0.0], radius=0.25),
           "box": dict(center=[0.0, -0.35, 0.0], size=[0.5, 0.3, 0.5]),
           "capsule": dict(center=[0.0, -0.35, 0.0], radius=0.15)}[obj]
    s = scene(forces__rain=True, forces__rain_strength=strength, forces__rain_rate=rate,
              scene__thickness=thickness, behavior__seed=seed, cloth__resolution=16)
    s.objects = [SceneObject(type=obj, **low)]
    st_ = run(Simulation(s), 20).stats()
    assert st_.finite and st_.penetration <= thickness + SLACK, st_.penetration


@settings(max_examples=10, deadline=None, suppress_health_check=[HealthCheck.too_slow])
@given(normal=st.tuples(*[st.floats(-1, 1)] * 3).filter(lambda v: math.hypot(*v) > 0.1),
       offset=st.floats(-0.3, 0.3), thickness=st.sampled_from([0.0, 0.005, 0.05]),
       gravity=log_uniform(1.0, 1e3))
def test_a_free_sheet_straddling_a_plane_stays_on_its_sides(normal, offset, thickness, gravity):
    s = scene(cloth__pinned="none", cloth__resolution=16, scene__thickness=thickness,
              forces__gravity_strength=gravity)
    s.objects = [SceneObject(type="plane", center=[offset, 0.25, 0.0], normal=list(normal))]
    st_ = run(Simulation(s), 20).stats()
    assert st_.finite and st_.penetration <= thickness + SLACK, st_.penetration
