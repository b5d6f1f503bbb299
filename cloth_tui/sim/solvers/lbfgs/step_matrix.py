"""The constant matrix P = M/h² + θ·(Σ_edges k_e A_eᵀA_e + Σ_cells w_c (diagonals) + Q_B), one
N×N matrix for x, y and z alike, factored once per substep length and pin set (and kept for a
step made again with the same: `kept_factor`).

It is the Hessian of the step's objective (step_energy.py) with every edge held at its rest
length and no geometric stiffness: exact for the bending energy (linear stencils: Q_B is its
Hessian), the stretch and shear as springs along their lines. L-BFGS
starts each step from P⁻¹ and learns what it misses (the sheet's turning) from its
gradients. A held particle's row and column are the identity, so it never moves.

Factored by SciPy's SuperLU with a minimum-degree ordering of AᵀA + A: on a grid its fill
grows as N log N, and so does a solve. The factor is single precision: P⁻¹ is only where
L-BFGS starts (the objective, its gradient and the line search stay in double, so the step
still ends at the same minimum), and a solve is bound by reading the factor, half the bytes
in single precision."""

from __future__ import annotations

import weakref

import numpy as np

# Factors kept for steps made again: the accuracy control moves a sheet between two substep
# counts, and each change builds a new step (a large sheet's factor is a visible pause to
# make and tens of MB to keep).
FACTORS_KEPT = 2
_kept: list = []  # (model's weak reference, the matrix's inputs, factor), the latest last


def shear_weight(fabric) -> float:
    """N/m: a shear cell's energy k_c γ²/2 on each of its diagonals as a spring, the
    Gauss-Newton weight k_c |∂γ/∂d|² = k_c (2·scale·|d|)² at rest."""
    g = fabric.grid
    scale = 1.0 / (4 * g.dx * g.dz)
    return 4 * scale * scale * (g.dx * g.dx + g.dz * g.dz) / fabric.cell_compliance


def step_matrix(model, k_edge: np.ndarray, k_stencil: np.ndarray, h: float, theta: float):
    """P as a SciPy CSC matrix (module docstring), for `model`'s held particles now;
    `k_stencil` = 1/α_s per bending stencil (its rigidity × weight, by direction)."""
    import scipy.sparse as sp

    n = model.num_particles
    e = model.edges
    rows = [e[:, 0], e[:, 1], e[:, 0], e[:, 1]]
    cols = [e[:, 1], e[:, 0], e[:, 0], e[:, 1]]
    vals = [-k_edge, -k_edge, k_edge, k_edge]
    f = model.fabric
    if f is not None and f.num_cells:
        w = np.full(f.num_cells, shear_weight(f))
        for a, b in ((f.cells[:, 0], f.cells[:, 3]), (f.cells[:, 1], f.cells[:, 2])):
            rows += [a, b, a, b]
            cols += [b, a, a, b]
            vals += [-w, -w, w, w]
    if f is not None and f.stencils is not None:  # Q_B = Σ_s k_s D_sᵀD_s, exactly
        p, c = f.stencils.particles, f.stencils.coeffs
        rows.append(np.repeat(p, 4, axis=1).ravel())
        cols.append(np.tile(p, (1, 4)).ravel())
        vals.append((k_stencil[:, None, None] * c[:, :, None] * c[:, None, :]).ravel())
    r = np.concatenate(rows)
    c = np.concatenate(cols)
    v = theta * np.concatenate(vals)
    free = model.inv_mass > 0
    keep = free[r] & free[c]
    diag = np.where(free, model.mass / (h * h), 1.0)
    everyone = np.arange(n)
    return sp.coo_matrix((np.concatenate([v[keep], diag]),
                          (np.concatenate([r[keep], everyone]),
                           np.concatenate([c[keep], everyone]))), shape=(n, n)).tocsc()


class SinglePrecisionFactor:
    """P's LU factors in single precision; `.solve(b)` takes and gives double (N, 3)."""

    def __init__(self, matrix):
        from scipy.sparse.linalg import splu
        self._lu = splu(matrix.astype(np.float32), permc_spec="MMD_AT_PLUS_A",
                        options={"SymmetricMode": True})

    def solve(self, b: np.ndarray) -> np.ndarray:
        return self._lu.solve(b.astype(np.float32)).astype(np.float64)


def factor(matrix) -> SinglePrecisionFactor:
    """A solver for P: `.solve(b)` with b (N, 3)."""
    return SinglePrecisionFactor(matrix)


def kept_factor(model, k_edge: np.ndarray, k_stencil: np.ndarray, h: float):
    """factor(step_matrix(...)) for `model`'s held particles now, the same object again
    where one of the last FACTORS_KEPT was made from the same inputs."""
    inputs = (h, (model.inv_mass == 0).tobytes(), k_edge.tobytes(), k_stencil.tobytes())
    _kept[:] = [entry for entry in _kept if entry[0]() is not None]  # (a sheet let go)
    for entry in _kept:
        ref, made_from, lu = entry
        if ref() is model and made_from == inputs:
            _kept.remove(entry)
            _kept.append(entry)
            return lu
    lu = factor(step_matrix(model, k_edge, k_stencil, h, 1.0))
    _kept.append((weakref.ref(model), inputs, lu))
    del _kept[:-FACTORS_KEPT]
    return lu
