"""The guard halts only for divergence: position-based runs at the extremes of mass, frame rate
and speed limit simulate (issue 19: pbd halted where nothing diverged)."""

import math

import numpy as np
from hypothesis import HealthCheck, given, settings
from hypothesis import strategies as st

from cloth_tui.sim.run.runner import Simulation

from ..helpers import run, scene


def log_uniform(lo: float, hi: float):
    # clamped: exp(log(hi)) may round a hair above hi, which the key's range refuses
    return st.floats(math.log(lo), math.log(hi)).map(lambda v: min(hi, max(lo, math.exp(v))))


@settings(max_examples=25, deadline=None, suppress_health_check=[HealthCheck.too_slow])
@given(solver=st.sampled_from(["pbd", "xpbd"]), mass=log_uniform(1e-6, 1e6),
       frame_rate=log_uniform(1.0, 1e4), max_speed=log_uniform(1e-5, 1e5),
       substeps=st.integers(1, 64), thickness=st.sampled_from([0.005, 0.2]))
def test_position_based_runs_at_extreme_settings_never_halt(solver, mass, frame_rate, max_speed,
                                                            substeps, thickness):
    # A sphere under the sheet's middle, within the skin when it is thick: its first push, over
    # a substep of microseconds, is a speed far beyond max_speed that moves nothing further.
    s = scene(behavior__solver=solver, cloth__mass=mass, behavior__frame_rate=frame_rate,
              behavior__max_speed=max_speed, behavior__substeps=substeps,
              behavior__adaptive=False, cloth__resolution=8, scene__thickness=thickness,
              scene__object="sphere", cloth__height=0.1)
    s.objects = []
    sim = run(Simulation(s), 4)
    st_ = sim.stats()
    assert st_.halted is None and st_.finite, st_.halted
    free = sim.model.inv_mass > 0
    speeds = np.linalg.norm(sim.state.v[free], axis=1)
    assert speeds.max() <= max_speed * (1 + 1e-9)
