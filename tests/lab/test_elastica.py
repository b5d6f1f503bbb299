"""The heavy elastica and the Peirce test: the published tip deflections, the linear
theory's limit, and the ASTM D1388 rule B = w(O/2)³ giving back the rigidity it started
from."""

import math

import pytest

from cloth_tui.lab.elastica import MAX_LOAD, cantilever, load_for_chord_angle
from cloth_tui.lab.peirce import PEIRCE_ANGLE, overhang, peirce_load, peirce_rigidity
from cloth_tui.materials.presets import get_preset


@pytest.mark.parametrize("load, drop", [(2, 0.2385), (8, 0.6406), (20, 0.8299)])
def test_the_published_tip_deflections(load, drop):
    assert cantilever(load).tip_drop == pytest.approx(drop, abs=5e-5)


@pytest.mark.parametrize("load, reach, slope, chord", [
    (2, 0.9669, 18.43, 13.86), (8, 0.7244, 53.86, 41.49), (20, 0.4452, 76.75, 61.79),
    (100, 0.1592, 89.62, 80.36)])
def test_the_reference_shapes(load, reach, slope, chord):
    # the project's reference notes, solved there by RK4 shooting of their own
    c = cantilever(load)
    assert c.reach == pytest.approx(reach, abs=5e-5)
    assert math.degrees(c.tip_slope) == pytest.approx(slope, abs=0.005)
    assert math.degrees(c.chord_angle) == pytest.approx(chord, abs=0.005)


def test_a_light_load_bends_as_the_linear_beam():
    # small deflection: δ = wL⁴/(8B), tip slope wL³/(6B), clamp curvature wL²/(2B)
    c = cantilever(0.01)
    assert c.tip_drop == pytest.approx(0.01 / 8, rel=1e-3)
    assert c.tip_slope == pytest.approx(0.01 / 6, rel=1e-3)
    assert c.clamp_curvature == pytest.approx(0.01 / 2, rel=1e-3)


def test_the_strip_keeps_its_length_and_hangs_more_under_more_load():
    drops = [cantilever(load) for load in (1, 4, 16, 64, MAX_LOAD)]
    assert all(a.tip_drop < b.tip_drop for a, b in zip(drops, drops[1:]))
    for c in drops:
        assert math.hypot(c.reach, c.tip_drop) < 1.0  # the chord is shorter than the strip
        assert c.tip_slope < math.pi / 2


@pytest.mark.parametrize("load", [0, -1, MAX_LOAD * 2, math.inf, math.nan])
def test_a_load_outside_the_solved_range_is_refused(load):
    with pytest.raises(ValueError, match="wL³/B must be in"):
        cantilever(load)


def test_the_peirce_angle_is_at_the_load_of_8():
    """41.5° is where the exact elastica puts the tip line at wL³/B = 8.004, so the
    standard's c = O/2 holds to 0.02 %."""
    load = peirce_load()
    assert load == pytest.approx(8.004, abs=5e-4)
    assert math.degrees(cantilever(load).chord_angle) == pytest.approx(41.5, abs=1e-9)
    assert load ** (-1 / 3) == pytest.approx(0.4999, abs=5e-5)
    assert load_for_chord_angle(math.radians(13.86)) == pytest.approx(2.0, rel=1e-3)


@pytest.mark.parametrize("name", ["denim", "jersey", "wang2011-royal-target", "leather"])
def test_the_peirce_rule_gives_back_the_rigidity(name):
    p = get_preset(name)
    o = overhang(p.bending, p.areal_density)
    assert peirce_rigidity(p.areal_density, o) == pytest.approx(p.bending, rel=1e-3)
    # the overhang's strip does show the 41.5° line
    load = p.areal_density * 9.81 * o ** 3 / p.bending
    assert cantilever(load).chord_angle == pytest.approx(PEIRCE_ANGLE, abs=1e-9)
