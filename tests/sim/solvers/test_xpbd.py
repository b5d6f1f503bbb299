"""XPBD: compliant constraints whose stiffness does not depend on the iteration count."""

import dataclasses

import numpy as np
import pytest

from cloth_tui.bench import accuracy as A
from cloth_tui.scene import Scene
from cloth_tui.sim.run.runner import Simulation


@pytest.fixture(scope="module")
def sag():
    cfg = dataclasses.replace(A.StudyConfig(), sag_iterations=(4, 64), sag_t_end=1.5)
    return A.sag_study(cfg)


def test_xpbd_sag_independent_of_iterations_while_pbd_is_not(sag):
    x, p = sag["sag"]["xpbd"], sag["sag"]["pbd"]
    assert abs(x["4"] - x["64"]) < 0.05 * x["64"]
    assert abs(p["4"] - p["64"]) > 0.3 * p["64"]
    assert sag["spread"]["xpbd"] < sag["spread"]["pbd"]


def test_xpbd_converges_to_springs_of_stiffness_one_over_compliance(sag):
    assert sag["sag"]["xpbd"]["64"] == pytest.approx(sag["springs_implicit_euler"], rel=0.05)


def test_xpbd_with_zero_compliance_is_pbd():
    def run(solver):
        s = Scene().with_value("cloth.resolution", 10).with_value("behavior.solver", solver)
        s = s.with_value("behavior.compliance", 0.0)
        sim = Simulation(s)
        for _ in range(30):
            sim.advance_frame()
        return sim.state.x

    np.testing.assert_allclose(run("xpbd"), run("pbd"), atol=1e-9)


def test_xpbd_pipeline_and_pins():
    s = Scene().with_value("cloth.resolution", 10).with_value("behavior.solver", "xpbd")
    s = s.with_value("behavior.compliance", 1e-3)
    sim = Simulation(s)
    assert "project_xpbd_constraints" in sim.step.names
    for _ in range(60):
        sim.advance_frame()
    m = sim.model
    np.testing.assert_array_equal(sim.state.x[m.pinned], m.rest_positions[m.pinned])
    assert sim.state.is_finite() and sim.recoveries == 0


def test_xpbd_stiffness_independent_of_timestep():
    """The same compliance gives the same settled sag at 2 and 8 substeps per frame."""
    sags = []
    for sub in (2, 8):
        cfg = dataclasses.replace(A.StudyConfig(), sag_iterations=(16,), sag_t_end=1.5,
                                  sag_substeps=sub)
        sags.append(A.sag_study(cfg)["sag"]["xpbd"]["16"])
    assert sags[0] == pytest.approx(sags[1], rel=0.05)
