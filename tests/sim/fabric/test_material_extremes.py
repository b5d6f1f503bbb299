"""Every value the [material] schema accepts makes a run that survives: the smallest
positive numbers (5e-324, the least double) and the largest allowed end with finite
statistics, valid JSON and no RuntimeWarning, by hpbd and xpbd alike."""

import json
import math
import warnings

import pytest

from cloth_tui.scene import Scene
from cloth_tui.sim.run.runner import Simulation

BASE = {"areal_density": 0.2, "stretch": 100.0, "shear": 10.0, "bending": 1e-6}
TINY = 5e-324


def run(material: dict, solver: str, frames: int = 6, **values):
    s = Scene().with_values({"cloth.resolution": 8, "behavior.solver": solver,
                             "material": {**BASE, **material}, **values})
    with warnings.catch_warnings():
        warnings.simplefilter("error")  # a RuntimeWarning (overflow, 0/0) fails the test
        sim = Simulation(s)
        for _ in range(frames):
            sim.advance_frame()
        return sim.stats()


@pytest.mark.parametrize("solver", ["hpbd", "xpbd"])
@pytest.mark.parametrize("key, value", [
    ("areal_density", TINY), ("stretch", TINY), ("shear", TINY), ("bending", TINY),
    ("shear", 1e-300), ("bending", 1e-300), ("areal_density", 100.0), ("stretch", 1e7),
    ("shear", 1e7), ("bending", 10.0), ("damping", 1e3)])
def test_extreme_material_values_run_with_finite_statistics(key, value, solver):
    st = run({key: value}, solver)
    assert st.finite and st.halted is None, (st.finite, st.halted)
    assert math.isfinite(st.energy) and math.isfinite(st.error), (st.energy, st.error)
    json.dumps(st.as_dict(), allow_nan=False)


def test_a_tear_strength_of_the_least_double_tears_everything_and_runs_on():
    st = run({"tear_strength": TINY}, "xpbd", **{"behavior.tear": True})
    assert st.finite and st.halted is None
    assert st.torn == st.constraints  # no edge holds the sheet's own weight
