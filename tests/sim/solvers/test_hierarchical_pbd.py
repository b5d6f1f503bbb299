"""Hierarchical PBD reaches the equilibrium of Gauss-Seidel PBD run to convergence, at the
default accuracy: a hanging sheet, a sheet draped on a sphere with friction, a torn sheet.

The reference is plain pbd at 32 substeps of 8 passes (its solve error a tenth of the
tolerance or less). "Within the accuracy": every particle within τ·L/2 of the reference
(τ the error tolerance, L the sheet's side: what a τ stretch moves a particle half a sheet
from its pin). hpbd runs the scene's default settings, adaptive substeps included."""

import numpy as np
import pytest

from cloth_tui.sim.solvers.hpbd.position_levels import ProjectHierarchy
from cloth_tui.sim.run.runner import Simulation
from cloth_tui.sim.state import ClothState
from cloth_tui.sim.solvers.xpbd.constraints import ProjectConstraints

from ..helpers import run, scene

N = 24
FRAMES = 150
CONVERGED = {"behavior__adaptive": False, "behavior__substeps": 32, "behavior__iterations": 8}
# a settled state in FRAMES frames (the default's 0.03 leaves the sheet swinging)
SETTLE = {"cloth__resolution": N, "behavior__damping": 0.2}
CASES = {
    "hanging": {},
    "draped": {"scene__object": "sphere", "scene__friction": 0.9, "cloth__height": 0.008},
    "torn": {"behavior__tear": True, "behavior__tear_stretch": 50.0},
}


def settled(case: str, **keys) -> Simulation:
    sim = Simulation(scene(**SETTLE, **CASES[case], **keys))
    if case == "torn":  # across the middle: two halves, each hanging from two corners
        row = sim.model.nz // 2
        assert sim.cut(row * sim.model.nx, (row + 1) * sim.model.nx - 1) > 0
    return run(sim, FRAMES)


@pytest.mark.parametrize("case", sorted(CASES))
def test_hpbd_reaches_the_converged_equilibrium(case):
    ref = settled(case, behavior__solver="pbd", **CONVERGED)
    sim = settled(case, behavior__solver="hpbd")
    tol = sim.scene.behavior.error_tolerance
    assert ref.stats().error < 0.1 * tol
    stats = sim.stats()
    assert stats.finite and stats.error <= tol and stats.tolerance_met
    gap = np.linalg.norm(sim.state.x - ref.state.x, axis=1).max()
    assert gap <= tol * sim.model.extent / 2, f"{case}: {gap:.4f} m from the converged sheet"
    if case == "draped":
        (sphere,) = [c for c in sim.step.colliders if "sphere" in c.name]
        assert (sphere.signed_distance(sim.state.x) < 2 * sphere.thickness).sum() > 0
    if case == "torn":  # the halves came apart where they were cut
        m, x = sim.model, sim.state.x.reshape(sim.model.nz, sim.model.nx, 3)
        row = m.nz // 2
        assert sim.state.torn and np.linalg.norm(x[row, :] - x[row + 1, :], axis=1).max() \
            > 0.1 * m.extent


def test_coarse_levels_carry_a_stretch_across_the_sheet():
    """A free sheet stretched 20 % everywhere: one cascade takes out most of it, where fine
    Gauss-Seidel passes, each carrying a correction about one particle, leave the sheet's
    edges more stretched than before."""
    sim = Simulation(scene(cloth__resolution=33, cloth__pinned="none",
                           behavior__solver="hpbd"))
    st = ClothState.from_model(sim.model)
    st.x[:] *= np.array([1.2, 1.0, 1.2])
    m = sim.model

    def worst_stretch(x):
        lengths = np.linalg.norm(x[m.edges[:, 1]] - x[m.edges[:, 0]], axis=1)
        return np.abs(lengths / m.rest_length - 1).max()

    assert worst_stretch(st.x) > 0.19
    fine = st.copy()
    ProjectConstraints(m, 8, 0.0, 1e-3, "fine").apply(fine, 1e-3)
    assert worst_stretch(fine.x) > 0.2
    ProjectHierarchy(m).apply(st, 1e-3)
    assert worst_stretch(st.x) < 0.1


def test_a_compressed_sheet_is_left_alone():
    """Coarse constraints are one-sided: a sheet shrunk in its plane (as if folded) gets no
    coarse correction."""
    sim = Simulation(scene(cloth__resolution=17, cloth__pinned="none"))
    st = ClothState.from_model(sim.model)
    st.x[:] *= np.array([0.9, 1.0, 0.9])
    before = st.x.copy()
    ProjectHierarchy(sim.model).apply(st, 1e-3)
    assert np.abs(st.x - before).max() < 1e-12


def test_hpbd_meets_the_tolerance_in_fewer_substeps_as_the_sheet_grows():
    """The original scene, adaptive: the work the tolerance costs. pbd's substeps grow with
    the sheet (a pass carries a correction one particle); hpbd's stay at the scene's floor."""
    runs = {}
    for n in (24, 48):
        for solver in ("pbd", "hpbd"):
            sim = run(Simulation(scene(cloth__resolution=n, behavior__solver=solver)), 30)
            assert sim.control.met
            runs[n, solver] = sim.substeps_run
    floor = 30 * scene().behavior.substeps
    assert runs[24, "hpbd"] == runs[48, "hpbd"] == floor
    assert runs[48, "pbd"] > 3 * runs[48, "hpbd"] and runs[48, "pbd"] > runs[24, "pbd"]


def test_a_new_mass_reaches_the_coarse_levels_without_a_rebuild():
    sim = Simulation(scene(cloth__resolution=17, behavior__solver="hpbd"))
    (cascade,) = [e for e in sim.step.effects if isinstance(e, ProjectHierarchy)]
    before = cascade._w.copy()
    plans = cascade._plans
    swept = [plan.inv_mass[plan.grid_offset].copy() for plan, _ in plans]
    assert not sim.set_scene(sim.scene.with_value("behavior.damping", 0.1))
    assert cascade._plans is plans  # the masses did not change: nothing rebuilt
    assert not sim.set_scene(sim.scene.with_value("cloth.mass", 2 * sim.scene.cloth.mass))
    (same,) = [e for e in sim.step.effects if isinstance(e, ProjectHierarchy)]
    assert same is cascade
    np.testing.assert_allclose(cascade._w, before / 2)
    for (plan, _), w in zip(plans, swept):  # the sweeps' copy too
        np.testing.assert_allclose(plan.inv_mass[plan.grid_offset], w / 2)
    run(sim, 3)
    assert sim.stats().finite


@pytest.mark.parametrize("n,torn", [(17, False), (26, False), (33, True), (42, True)])
def test_the_sweeps_give_the_plain_loops_positions(n, torn):
    """The cascade as grid_sweeps' colour runs moves every particle as the plain loop over
    each level's constraint list does (the same colours in the same order), a cut
    included."""
    from cloth_tui.sim.solvers.hpbd.position_levels import cascade_loop

    sim = Simulation(scene(cloth__resolution=n, behavior__solver="hpbd",
                           behavior__tear=torn))
    if torn:
        row = sim.model.nz // 2
        assert sim.cut(row * sim.model.nx, row * sim.model.nx + n // 2) > 0
    (ph,) = [e for e in sim.step.effects if isinstance(e, ProjectHierarchy)]
    rng = np.random.default_rng(n)
    st = sim.state.copy()
    st.x[:] = st.x * np.array([1.15, 1.0, 1.1]) + rng.normal(0.0, 0.003, st.x.shape)
    start, loop = st.x.copy(), st.x.copy()
    ph.apply(st, 1e-3)  # (takes the cut into its flags, which the loop then reads)
    cascade_loop(loop, ph._r, ph._p, ph._total, ph._node_off, ph._w, ph._own, ph._edge_off,
                 ph._edges, ph._rest, ph._alive, ph._fine_off, ph._sources, ph._weights,
                 ph._free, ph._cell_alive, ph._passes)
    assert np.abs(st.x - start).max() > 1e-3  # the cascade moved the sheet
    np.testing.assert_allclose(st.x, loop, rtol=0, atol=1e-12)
