"""The clamped strip's geometry and the Peirce search, without the simulator: the strip's
free length for a load, the clamp's half cell, and the secant search for the 41.5° line run
on the exact elastica (where it must find the overhang peirce.overhang computes)."""

import math

import pytest

from cloth_tui.lab import clamped
from cloth_tui.lab.elastica import cantilever
from cloth_tui.lab.peirce import PEIRCE_ANGLE, overhang, peirce_rigidity
from cloth_tui.lab.study import LabError, lab_material


def test_the_free_length_gives_the_load():
    denim = lab_material("denim")
    for load in clamped.CANTILEVER_LOADS:
        L = clamped.strip_for_load(load, denim)
        B = clamped.strip_bending(denim)   # the warp strip's: denim bends by direction
        assert denim.areal_density * 9.81 * L ** 3 / B == pytest.approx(load)
        L = clamped.strip_for_load(load, denim, "weft")
        B = clamped.strip_bending(denim, "weft")
        assert denim.areal_density * 9.81 * L ** 3 / B == pytest.approx(load)


def test_a_fabric_that_bends_by_direction_gets_a_peirce_strip_each_way():
    denim = lab_material("denim")
    folds = denim.bending_by_direction
    cases = clamped.PEIRCE.cases(denim)
    assert [c.params["direction"] for c in cases] == ["warp", "weft"]
    # the warp strip curves along x: a fold across the warp, at 90° to it
    assert [c.expected for c in cases] == [folds.fold_90, folds.fold_0]
    (one,) = clamped.PEIRCE.cases(lab_material("cotton"))   # linear: one strip
    assert one.expected == lab_material("cotton").bending


def test_the_clamps_edge_is_half_a_cell_beyond_the_last_held_column():
    assert clamped.free_length_spacing(0.105, 10) == pytest.approx(0.01)
    assert (40 + 0.5) * clamped.free_length_spacing(0.3, 40) == pytest.approx(0.3)


def test_the_cantilever_cases_are_the_elasticas():
    cases = clamped.CANTILEVER.cases(None)
    assert [c.params["load"] for c in cases] == [2.0, 8.0, 20.0]
    assert [round(c.expected, 4) for c in cases] == [0.2385, 0.6406, 0.8299]


def elastica_chord(bending, density):
    """The chord angle a strip of rigidity `bending` shows at overhang O: the exact answer
    a perfect simulator would give."""
    return lambda overhang: cantilever(density * 9.81 * overhang ** 3 / bending).chord_angle


@pytest.mark.parametrize("preset", clamped.PEIRCE_PRESETS)
def test_the_peirce_search_finds_the_elasticas_overhang(preset):
    m = lab_material(preset)
    found, runs = clamped.peirce_search(elastica_chord(m.bending, m.areal_density),
                                        overhang(m.bending, m.areal_density))
    assert found == pytest.approx(overhang(m.bending, m.areal_density), rel=1e-4)
    assert peirce_rigidity(m.areal_density, found) == pytest.approx(m.bending, rel=1e-3)
    assert runs <= 4


def test_the_peirce_search_follows_a_stiffer_strip():
    """A simulator 10 % too stiff shows the 41.5° line at a longer overhang, and the
    standard's B then comes out 10 % high: the search reports the simulator, not the
    table."""
    m = lab_material("denim")
    stiff = elastica_chord(1.1 * m.bending, m.areal_density)
    found, _ = clamped.peirce_search(stiff, overhang(m.bending, m.areal_density))
    assert stiff(found) == pytest.approx(PEIRCE_ANGLE, abs=clamped.PEIRCE_ANGLE_TOLERANCE)
    assert peirce_rigidity(m.areal_density, found) / m.bending == pytest.approx(1.1, rel=2e-3)


def test_a_search_that_cannot_reach_the_angle_says_so():
    with pytest.raises(LabError, match="no overhang found for 41.5°"):
        clamped.peirce_search(lambda overhang: math.radians(10), 0.03)


def test_behaviour_keys_given_replace_the_labs_and_leave_the_rest():
    denim = lab_material("denim")
    length = clamped.strip_for_load(8.0, denim)
    lab, *_ = clamped.clamped_strip(length, 10, denim, "xpbd")
    given, *_ = clamped.clamped_strip(length, 10, denim, "xpbd",
                                      behavior={"iterations": 3, "adaptive": True})
    assert lab.behavior.iterations == clamped.ITERATIONS and not lab.behavior.adaptive
    assert given.behavior.iterations == 3 and given.behavior.adaptive
    assert given.behavior.substeps == lab.behavior.substeps
    assert given.behavior.solver == "xpbd"
