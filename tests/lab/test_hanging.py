"""The lab's catenary and swing, run on the simulator: the strip's sag and period against the
computed catenary and hanging chain (the Done-when bounds), and the run's own bookkeeping."""

import math

import numpy as np
import pytest

from cloth_tui.lab import hanging, study
from cloth_tui.lab.chain import bessel_j0_zero


@pytest.fixture(scope="module")
def catenary_run():
    return study.run(hanging.CATENARY, [8, 16, 32])


@pytest.fixture(scope="module")
def swing_run():
    return study.run(hanging.SWING, [8, 16, 32])


def test_catenary_sag_within_half_a_percent_from_16_links(catenary_run):
    (case,) = catenary_run["cases"]
    errors = {p["resolution"]: p["error"] for p in case["points"]}
    assert abs(errors[16]) < 0.005 and abs(errors[32]) < 0.005
    assert abs(errors[8]) > abs(errors[16]) > abs(errors[32])  # it converges, from above


def test_catenary_error_falls_as_h_squared(catenary_run):
    (case,) = catenary_run["cases"]
    assert case["order"] == pytest.approx(2.0, abs=0.5)


def test_catenary_solve_reaches_the_grids_own_equilibrium(catenary_run):
    """What is left is the discretisation's: the exact equilibrium of the same links with
    the same lumped masses is met within 0.01 %, far inside the error against the curve."""
    for p in catenary_run["cases"][0]["points"]:
        assert abs(p["solve_error"]) < 1e-4
        assert abs(p["solve_error"]) < abs(p["error"]) / 4


def test_swing_period_within_two_percent_of_the_chain(swing_run):
    (case,) = swing_run["cases"]
    assert case["expected"] == pytest.approx(
        2 * math.pi / (bessel_j0_zero(1) / 2 * math.sqrt(9.81 / 1.0)))
    for p in case["points"]:
        assert abs(p["error"]) < 0.02, p
        assert p["crossings"] >= 2 * hanging.SWING_PERIODS  # the period timed whole periods
    assert abs(case["points"][-1]["error"]) < 0.002


def test_the_swing_measure_finds_a_known_period():
    t = np.linspace(0, 5, 301)
    period, crossings = hanging.zero_crossing_period(t, np.cos(2 * math.pi * t / 1.25))
    assert period == pytest.approx(1.25, rel=1e-4) and crossings == 8
    assert math.isnan(hanging.zero_crossing_period(t, t + 1)[0])


def test_the_first_mode_is_held_at_the_top_and_free_at_the_tip():
    u = hanging.first_mode(1.0, np.array([0.0, 0.5, 1.0]))
    assert u[0] == pytest.approx(0.0, abs=1e-12) and u[-1] == pytest.approx(1.0)
    assert 0 < u[1] < 1


def test_a_material_sets_the_strips_mass_not_its_shape():
    """The catenary and the chain's period do not depend on the density: a preset changes
    the sheet's mass (density × area) and leaves the expectation as it is."""
    denim = study.lab_material("denim")
    scene = hanging.strip_scene(size=[1.0, 0.1], resolution=[9, 2], pins=[{"rows": [0, 0]}],
                                behavior={}, material=denim)
    assert scene.cloth.mass == pytest.approx(denim.areal_density * 0.1)
    assert hanging.CATENARY.cases(denim)[0].expected == hanging.CATENARY.cases(None)[0].expected
