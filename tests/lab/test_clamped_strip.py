"""The clamped strip run on the simulator with the lab's material: a strip of the scene format,
its [material] the preset, xpbd or hpbd, held by a pin group of three columns, settled until
its tip stands still. Its tip's drop is within 2 % of the heavy elastica at wL³/B = 2, 8, 20
from L/10 to L/40, and the Peirce test on it gives back the material's B within 2 % (the
warp strip's, and the weft strip's along z)."""

import pytest

from cloth_tui.lab import clamped
from cloth_tui.lab.elastica import cantilever
from cloth_tui.lab.study import lab_material

BOUND = 0.02


# Every load at 10 and 20 links; at 40 (2-3 s each) the middle load, the others marked slow.
TIP_DROP_CASES = [
    pytest.param(load, links, solver, id=f"{load}-{links}-{solver}",
                 marks=pytest.mark.slow if links == 40 and load != 8.0 else ())
    for load in clamped.CANTILEVER_LOADS for links in (10, 20, 40) for solver in ("xpbd", "hpbd")]


@pytest.mark.parametrize("load, links, solver", TIP_DROP_CASES)
def test_the_tip_drop_is_the_elasticas(load, links, solver):
    denim = lab_material("denim")
    length = clamped.strip_for_load(load, denim)
    r = clamped.settle_clamped(length, links, denim, solver)
    assert r["drop"] / length == pytest.approx(cantilever(load).tip_drop, rel=BOUND)
    assert r["max_stretch"] < 0.01  # it bends; it does not hang by stretching


def test_a_strip_at_rest_is_still_everywhere_and_a_jittering_one_is_not_called_settled():
    """Settled means the tip still for STILL_CHECKS checks and no particle faster than would
    move it SETTLED_DRIFT·L in one: a strip at rest passes with its particles a hundred times
    slower than that; lbfgs at the lab's iterations, whose solve jitters (its tip once read
    still three checks running), never does, and the error names its fastest particle."""
    from cloth_tui.lab.study import LabError

    denim = lab_material("denim")
    length = clamped.strip_for_load(8.0, denim)
    period = clamped.first_mode_period(length, denim, "warp")
    allowed = clamped.SETTLED_DRIFT * length / (clamped.CHECK_PERIODS * period)
    assert clamped.settle_clamped(length, 10, denim, "xpbd")["max_speed"] < allowed / 10
    with pytest.raises(LabError, match="fastest particle at"):
        clamped.settle_clamped(length, 10, denim, "lbfgs")


def test_a_finer_strip_takes_shorter_substeps():
    """The bending's stiffness per step grows as 1/dx⁴: h ∝ dx² keeps it bounded."""
    denim = lab_material("denim")
    coarse = clamped.substeps_for(0.002, denim, 60.0)
    fine = clamped.substeps_for(0.001, denim, 60.0)
    assert fine == pytest.approx(4 * coarse, rel=0.05)
    assert clamped.substeps_for(0.1, denim, 60.0) == clamped.SUBSTEPS


# hpbd at 40 links: 15 s a preset (its corrections cost more than they save on a strip);
# xpbd's 40 links are slow too, as the warp strips of jersey and tablecloth, limper than
# their weft, take the shorter overhang and the more substeps
@pytest.mark.parametrize("solver, links", [("xpbd", 10), ("xpbd", 20),
                                           pytest.param("xpbd", 40, marks=pytest.mark.slow),
                                           ("hpbd", 10), ("hpbd", 20)])
@pytest.mark.parametrize("preset", clamped.PEIRCE_PRESETS)
def test_the_peirce_test_gives_back_the_materials_bending(preset, links, solver):
    m = lab_material(preset)
    case = next(c for c in clamped.PEIRCE.cases(m))   # the strip cut along the warp
    result = clamped.PEIRCE.measure(case, links, m, solver)
    assert result.value == pytest.approx(m.bending_by_direction.fold_90, rel=BOUND)


@pytest.mark.parametrize("preset", ["denim", "jersey"])
def test_the_peirce_strip_cut_along_the_weft_gives_back_the_weft_bending(preset):
    """The strip along z: its B is the 0° fold's (denim's weft bends at 2/3 of its warp,
    jersey's at 1.6 times), which a strip along x of the same fabric does not show."""
    m = lab_material(preset)
    warp, weft = clamped.PEIRCE.cases(m)
    assert weft.params["direction"] == "weft"
    result = clamped.PEIRCE.measure(weft, 10, m, "xpbd")
    assert result.value == pytest.approx(m.bending_by_direction.fold_0, rel=BOUND)
    assert abs(result.value / warp.expected - 1) > 0.3
