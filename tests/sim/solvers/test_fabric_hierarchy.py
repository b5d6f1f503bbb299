"""hpbd with a material: the coarse corrections of the structural edges' λ
(sim/solvers/hpbd/multiplier_levels.py) solve XPBD's own system on a subspace, so they leave a
converged step as it is and speed up the rest; the sheet ends where converged xpbd puts it."""

import numpy as np
import pytest

from cloth_tui.scene import Scene
from cloth_tui.sim.solvers.hpbd.multiplier_levels import DualHierarchy, edge_aggregates
from cloth_tui.sim.run.runner import Simulation

from ..fabric.clipped_sheets import centre_height, clipped_sheet
from ..effects.pulled_strips import FRAME, first_tear, pulled_strip


def material_model(resolution, solver="hpbd", size=1.0):
    scene = Scene().with_values({"cloth.resolution": resolution, "cloth.size": size,
                                 "behavior.solver": solver,
                                 "material": {"preset": "denim"}})
    return Simulation(scene).model, scene


def test_the_aggregates_halve_each_axis_and_a_strip_goes_on_along_its_length():
    model, _ = material_model(17)
    levels = edge_aggregates(model)
    counts = [int(a.max()) + 1 for a in levels]
    assert counts[0] == 2 * 8 * 9 and counts == sorted(counts, reverse=True)
    strip, _ = material_model([40, 4])  # 40 particles along x, 4 rows
    levels = edge_aggregates(strip)
    _, cols = np.divmod(strip.edges[:, 0], strip.nx)
    along_x = strip.edges[:, 1] - strip.edges[:, 0] == 1
    last = levels[-1][along_x]
    # the last level's x-edge blocks: one across the strip's 4 rows, several along it
    assert len(levels) >= 4 and len(np.unique(last)) > 1
    assert all(len(np.unique(last[cols[along_x] == c])) == 1 for c in np.unique(cols[along_x]))


def dense_first_level(model, x, alpha_t, aggregate):
    """PᵀAP of the first level, A = J M⁻¹ Jᵀ + α̃ assembled densely from its definition."""
    e, w = model.edges, model.inv_mass
    n = x[e[:, 1]] - x[e[:, 0]]
    n /= np.linalg.norm(n, axis=1, keepdims=True)
    J = np.zeros((len(e), 3 * model.num_particles))
    for k, (a, b) in enumerate(e):
        J[k, 3 * a:3 * a + 3] = -n[k]
        J[k, 3 * b:3 * b + 3] = n[k]
    A = J @ np.diag(np.repeat(w, 3)) @ J.T + np.diag(alpha_t)
    P = np.zeros((len(e), int(aggregate.max()) + 1))
    P[np.arange(len(e)), aggregate] = 1.0
    return P.T @ A @ P


def test_the_coarse_matrix_is_the_galerkin_product_of_xpbds_system():
    model, _ = material_model(9)
    rng = np.random.default_rng(1)
    x = model.rest_positions + rng.normal(scale=0.01, size=model.rest_positions.shape)
    h = DualHierarchy(model)
    alpha_t = np.asarray(model.fabric.compliance) / (1 / 600) ** 2
    alive = np.ones(model.num_constraints, np.uint8)
    lam = np.zeros(model.num_constraints)
    slot = np.arange(model.num_constraints)
    h.correct(x.copy(), model.inv_mass, model.rest_length, alive, alpha_t, lam, slot)
    got = h.level_matrix(0)
    assert np.allclose(got, dense_first_level(model, x, alpha_t, h.aggregates[0]), rtol=1e-10)
    for k in range(1, len(h.levels)):  # each coarser level the product of the one below
        P = np.zeros((h.levels[k - 1].count, h.levels[k].count))
        P[np.arange(h.levels[k - 1].count), h.levels[k - 1].parent] = 1.0
        assert np.allclose(h.level_matrix(k), P.T @ h.level_matrix(k - 1) @ P, rtol=1e-10)
    assert len(h.levels) >= 2


def test_a_converged_step_is_left_as_it_is():
    """Where XPBD's passes have nothing left to do, neither has the coarse correction."""
    sim = Simulation(clipped_sheet(16, 10, 400).with_values({"behavior.solver": "xpbd"}))
    for _ in range(3):
        sim.advance_frame()
    stage = sim.step.solver.projection
    x = sim.state.x.copy()
    h = DualHierarchy(sim.model)
    lam, slot = stage.edges.slot_lambdas
    lam = lam.copy()
    before = x.copy()
    h.correct(x, sim.model.inv_mass, sim.model.rest_length, sim.state.alive,
              stage.edges.alpha_t, lam, slot)
    assert np.abs(x - before).max() < 1e-9  # m


def sag_error(cells, solver, substeps, iterations):
    sim = Simulation(clipped_sheet(cells, substeps, iterations).with_values(
        {"behavior.solver": solver}))
    for _ in range(120):
        sim.advance_frame()
    assert sim.stats().finite
    return 1.0 - centre_height(sim), sim


@pytest.mark.heavy
@pytest.mark.parametrize("cells", [48, pytest.param(64, marks=pytest.mark.slow)])
def test_hpbd_hangs_the_sheet_where_converged_xpbd_does_in_fewer_passes(cells):
    """At 10 substeps of 10 passes xpbd's sheet hangs too low (0.7 % at 48 cells, 1.3 % at
    64: the tension of a fine sheet is not through its passes); hpbd's within 0.1 % of xpbd
    at 40 substeps of 20 passes, and its solve error is lower."""
    converged = sag_error(cells, "xpbd", 40, 20)[0]
    fast, fast_sim = sag_error(cells, "hpbd", 10, 10)
    plain, plain_sim = sag_error(cells, "xpbd", 10, 10)
    assert abs(fast / converged - 1) < 1e-3
    assert abs(plain / converged - 1) > 5e-3
    assert fast_sim._solve_error() < 0.5 * plain_sim._solve_error()


@pytest.mark.parametrize("adaptive, substeps", [(True, 4), (False, 32)])
def test_a_strip_tears_by_its_strength_under_hpbd_when_xpbd_says(adaptive, substeps):
    """Tearing reads the λ the passes end with (the corrections' too): a strip pulled slowly
    tears when its strain reaches strength/stretch (test_tearing_by_strength's), with the
    accuracy control on and off."""
    sim = Simulation(pulled_strip(adaptive, substeps).with_values({"behavior.solver": "hpbd"}))
    assert "tear_by_strength" in sim.step.names and "project_fabric_levels" in sim.step.names
    at = first_tear(sim, 45)
    assert at is not None and 0.5 - FRAME / 2 <= at <= 0.5 + 2 * FRAME, at
