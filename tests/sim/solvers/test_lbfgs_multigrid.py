"""lbfgs's V-cycle (multigrid.py) stands for P⁻¹: within a few per cent of it on the default
fabric's sheet and on a strip, exact where the grid is small enough to solve directly,
symmetric and positive (L-BFGS's H₀ must be), the same after a new substep length as made
at it, and it never moves a held particle."""

import numpy as np
import pytest
import scipy.sparse.linalg as sla

from cloth_tui.bench.fabric_cost import clipped_fabric_scene
from cloth_tui.scene import Scene
from cloth_tui.sim.run.runner import Simulation
from cloth_tui.sim.solvers.lbfgs.multigrid import COARSEST, StepMultigrid
from cloth_tui.sim.solvers.lbfgs.step_matrix import stiffness_matrix, step_matrix

H = 1.0 / 120


def lbfgs_model(scene: Scene):
    sim = Simulation(scene.with_values({"behavior.solver": "lbfgs"}))
    return sim.model, sim.step.solver.projection


def denim_sheet(cells: int):
    return lbfgs_model(clipped_fabric_scene(cells, {"material": {"preset": "denim"}}))


def denim_strip():
    """A 3 × 401 strip held at one short end: too narrow to coarsen across, long enough to
    coarsen along."""
    return lbfgs_model(Scene().with_values({
        "cloth.size": [0.01, 2.0], "cloth.resolution": [3, 401], "cloth.pinned": "one_edge",
        "material": {"preset": "denim"}}))


def v_cycle(model, projection, h: float = H) -> StepMultigrid:
    cycle = StepMultigrid(stiffness_matrix(model, projection.k_edge, projection.k_sten),
                          model.mass, model.inv_mass == 0, model.nx, model.nz)
    cycle.set_step(h)
    return cycle


def exact(model, projection, b, h: float = H):
    return sla.spsolve(step_matrix(model, projection.k_edge, projection.k_sten, h).tocsc(), b)


def relative_error(approx, reference) -> float:
    return float(np.linalg.norm(approx - reference) / np.linalg.norm(reference))


def loads(model):
    """A rough load (random) and a smooth one (one sine along each axis), zero where held."""
    rng = np.random.default_rng(7)
    rough = rng.standard_normal((model.num_particles, 3))
    u = np.linspace(0.0, 1.0, model.nx)[None, :] * np.ones((model.nz, 1))
    w = np.linspace(0.0, 1.0, model.nz)[:, None] * np.ones((1, model.nx))
    smooth = np.stack([np.sin(np.pi * u), np.sin(np.pi * w), u * w], axis=-1).reshape(-1, 3)
    for b in (rough, smooth):
        b[model.inv_mass == 0] = 0.0
    return rough, smooth


@pytest.fixture(scope="module")
def sheet64():
    model, projection = denim_sheet(64)
    return model, projection, v_cycle(model, projection)


def test_one_cycle_is_within_a_few_percent_of_p_inverse_on_the_default_fabric(sheet64):
    model, projection, cycle = sheet64
    assert cycle.grids >= 3  # it does coarsen: 65² particles, then 33², 17²
    for b in loads(model):
        assert relative_error(cycle.solve(b), exact(model, projection, b)) < 0.05


def test_a_strip_coarsens_along_its_length_only_and_stays_close():
    model, projection = denim_strip()
    cycle = v_cycle(model, projection)
    assert model.nx == 3 and model.num_particles > COARSEST and cycle.grids >= 2
    for b in loads(model):
        assert relative_error(cycle.solve(b), exact(model, projection, b)) < 0.05


def test_a_grid_small_enough_is_solved_exactly():
    model, projection = denim_sheet(16)
    assert model.num_particles <= COARSEST
    cycle = v_cycle(model, projection)
    assert cycle.grids == 1
    for b in loads(model):
        assert relative_error(cycle.solve(b), exact(model, projection, b)) < 1e-10


def test_the_cycle_is_symmetric_and_positive(sheet64):
    """L-BFGS's H₀ must be SPD, or its directions need not descend."""
    model, _, cycle = sheet64
    rng = np.random.default_rng(11)
    u, v = (rng.standard_normal((model.num_particles, 3)) for _ in range(2))
    uv, vu = np.sum(u * cycle.solve(v)), np.sum(v * cycle.solve(u))
    assert abs(uv - vu) <= 1e-10 * np.sqrt(np.sum(u * u) * np.sum(v * v))
    for w in (u, v, u - v):
        assert np.sum(w * cycle.solve(w)) > 0.0


def test_a_new_substep_length_gives_the_cycle_made_at_it(sheet64):
    model, projection, cycle = sheet64
    b = loads(model)[0]
    cycle.set_step(H / 3)
    try:
        again = cycle.solve(b)
    finally:
        cycle.set_step(H)
    fresh = v_cycle(model, projection, H / 3).solve(b)
    assert np.allclose(again, fresh, rtol=1e-12, atol=1e-15 * np.abs(fresh).max())
    assert not np.allclose(again, cycle.solve(b))  # (the length does change the cycle)


def test_a_held_particle_is_never_moved(sheet64):
    model, _, cycle = sheet64
    held = model.inv_mass == 0
    assert held.any()
    b = np.random.default_rng(5).standard_normal((model.num_particles, 3))
    b[held] = 0.0
    assert np.all(cycle.solve(b)[held] == 0.0)


def test_two_sheets_alive_at_once_each_find_their_own_cycle():
    """The kept cycles are told apart by the model itself (a dataclass whose == compares its
    arrays: finding a cycle must not compare two models)."""
    from cloth_tui.sim.solvers.lbfgs.step_matrix import kept_preconditioner

    first, second = denim_sheet(16), denim_sheet(16)
    made = {}
    for model, projection in (first, second, second, first):  # (the latest is kept last)
        cycle = kept_preconditioner(model, projection.k_edge, projection.k_sten, H)
        assert made.setdefault(id(model), cycle) is cycle
    assert made[id(first[0])] is not made[id(second[0])]


def test_the_cycle_the_solver_uses_leaves_out_small_bending_and_stays_close(sheet64):
    """Denim's Q_B is a thousandth of its springs at 64²: the solver's cycle is made without
    it (shorter rows) and is still within a few per cent of P⁻¹ with it."""
    from cloth_tui.sim.solvers.lbfgs.step_matrix import (
        BENDING_SHARE, bending_share, kept_preconditioner)

    model, projection, with_bending = sheet64
    springs = stiffness_matrix(model, projection.k_edge, None)
    assert bending_share(model, springs, projection.k_sten) < BENDING_SHARE
    cycle = kept_preconditioner(model, projection.k_edge, projection.k_sten, H)
    assert len(cycle.indices) < len(with_bending.indices)
    for b in loads(model):
        assert relative_error(cycle.solve(b), exact(model, projection, b)) < 0.05


def test_bending_that_matters_stays_in_the_cycle():
    """A sheet 400× stiffer in bending reads a share above BENDING_SHARE, and its cycle keeps
    Q_B (rows as long as the full P's)."""
    from cloth_tui.sim.solvers.lbfgs.step_matrix import (
        BENDING_SHARE, bending_share, preconditioner_stiffness)

    model, projection = denim_sheet(32)
    stiff = 400.0 * projection.k_sten
    springs = stiffness_matrix(model, projection.k_edge, None)
    assert bending_share(model, springs, stiff) > BENDING_SHARE
    full = stiffness_matrix(model, projection.k_edge, stiff)
    assert preconditioner_stiffness(model, projection.k_edge, stiff).nnz == full.nnz > springs.nnz


def test_the_share_bounds_what_leaving_bending_out_changes():
    """BENDING_SHARE's reasoning: Q_B ≤ r·K_springs with r (the largest generalised
    eigenvalue) under 0.7 × the diagonal share, on the stiffest woven and the softest knit."""
    from cloth_tui.sim.solvers.lbfgs.step_matrix import bending_share

    for preset in ("denim", "wang2011-navy-sparkle-sweat"):
        scene = clipped_fabric_scene(16, {"material": {"preset": preset}})
        model, projection = lbfgs_model(scene)
        free = np.flatnonzero(model.inv_mass > 0)
        springs = stiffness_matrix(model, projection.k_edge, None)
        bending = stiffness_matrix(model, projection.k_edge, projection.k_sten) - springs
        k_s = springs[free][:, free].tocsc()
        q = bending[free][:, free].tocsr()
        factor = sla.splu(k_s)
        operator = sla.LinearOperator(k_s.shape, matvec=lambda v: factor.solve(q @ v))
        r = abs(sla.eigs(operator, k=1, which="LM", return_eigenvectors=False)[0])
        share = bending_share(model, springs, projection.k_sten)
        assert 0.0 < r <= 0.7 * share


def test_the_first_sweep_and_its_residual_are_gauss_seidels_from_zero(sheet64):
    """The cycle's way down reads half of P twice where a sweep and b − Px read all of it
    twice: the same numbers, to rounding."""
    from cloth_tui.sim.solvers.lbfgs.multigrid import (
        gauss_seidel_sweep, residual_after_sweep, sweep_from_zero)

    model, projection, cycle = sheet64
    rows = cycle.row_at[1]  # the sheet's own grid
    ptr, diag = cycle.ptr[:rows + 1], cycle.on_diagonal[:rows]
    matrix = step_matrix(model, projection.k_edge, projection.k_sten, H)
    b = np.random.default_rng(3).standard_normal((rows, 3))
    reference = np.zeros((rows, 3))
    gauss_seidel_sweep(ptr, cycle.indices, cycle.data, cycle.inv_diag[:rows], reference, b,
                       True)
    x, rest = np.full((rows, 3), np.nan), np.zeros((rows, 3))  # (x is written, never read)
    sweep_from_zero(ptr, cycle.indices, cycle.data, cycle.inv_diag[:rows], diag, x, b)
    residual_after_sweep(ptr, cycle.indices, cycle.data, diag, x, rest)
    assert np.allclose(x, reference, rtol=1e-12, atol=1e-14 * np.abs(reference).max())
    exact_rest = b - matrix @ x
    assert np.allclose(rest, exact_rest, rtol=1e-9, atol=1e-12 * np.abs(b).max())


def test_the_coarsest_grid_is_factored_as_lapack_would_and_a_bad_pivot_reads_nan():
    from cloth_tui.sim.solvers.lbfgs.multigrid import cholesky_factor

    a = np.random.default_rng(11).standard_normal((40, 40))
    a = a @ a.T + 40 * np.eye(40)
    factor = np.empty_like(a)
    cholesky_factor(a, factor)
    assert np.allclose(factor, np.linalg.cholesky(a), rtol=1e-12, atol=1e-12)
    a[5, 5] = -1.0  # not positive definite
    cholesky_factor(a, factor)
    lower = np.tril_indices(35)
    assert np.isnan(factor[5:, 5:][lower]).all() and np.isfinite(factor[:5, :5]).all()
