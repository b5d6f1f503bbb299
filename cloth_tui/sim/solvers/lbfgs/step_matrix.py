"""The constant matrix P = M/h² + Σ_edges k_e A_eᵀA_e + Σ_cells w_c (diagonals) + Q_B, one
N×N matrix for x, y and z alike, and the V-cycle that stands for its inverse (multigrid.py),
made once per pin set and stiffness and kept for a step made again with the same
(`kept_preconditioner`); a new substep length h only adds M/h² again.

It is the Hessian of the step's objective (step_energy.py) with every edge held at its rest
length and no geometric stiffness: exact for the bending energy (linear stencils: Q_B is its
Hessian), the stretch and shear as springs along their lines. L-BFGS
starts each step from P⁻¹ and learns what it misses (the sheet's turning) from its
gradients. A held particle's row and column are the identity, so it never moves.

The V-cycle leaves Q_B out where it is too small to matter (`bending_share`): a fabric's
bending is weak beside its stretch (denim at 128²: 6 N/m on the diagonal beside the springs'
4,930), yet its stencils reach two particles away and made the finest grid's rows 12.8
entries long instead of 8.9, and every sweep of the V-cycle reads every entry."""

from __future__ import annotations

import math
import weakref

import numpy as np

from .multigrid import StepMultigrid

# V-cycles kept for steps made again: the accuracy control and the guard build a new step at
# each change of the substeps, and a frame redone from before a tear goes back to the
# stiffness it had (a large sheet's coarse grids take a visible moment to make).
KEPT = 2
# Q_B is left out of the V-cycle's P while its largest diagonal entry is under this share of
# the springs' smallest. Measured on every preset at 16 and 64 cells, Q_B ≤ r·(the springs'
# part) with r ≤ 0.68 × that ratio (the largest generalised eigenvalue), so leaving it out
# moves P by at most 3.4 % (P' ≤ P ≤ (1 + r)P'), no more than the V-cycle's own distance
# from P⁻¹. The ratio grows as 1/dx²: denim reads 0.006 at 128² and 0.022 at 256², and the
# softest knit (navy sparkle sweat) keeps Q_B from 64² on.
BENDING_SHARE = 0.05
_kept: list = []  # (model's weak reference, the stiffness's inputs, V-cycle), the latest last


def shear_weight(fabric) -> float:
    """N/m: a shear cell's energy k_c γ²/2 on each of its diagonals as a spring, the
    Gauss-Newton weight k_c |∂γ/∂d|² = k_c (2·scale·|d|)² at rest."""
    g = fabric.grid
    scale = 1.0 / (4 * g.dx * g.dz)
    return 4 * scale * scale * (g.dx * g.dx + g.dz * g.dz) / fabric.cell_compliance


def stiffness_matrix(model, k_edge: np.ndarray, k_stencil: np.ndarray | None):
    """K = Σ_edges k_e A_eᵀA_e + Σ_cells w_c (diagonals) + Q_B as a SciPy CSR matrix, its
    held particles' rows and columns empty; `k_stencil` = 1/α_s per bending stencil (its
    rigidity × weight, by direction), None for K without Q_B."""
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
    if f is not None and f.stencils is not None and k_stencil is not None:
        # Q_B = Σ_s k_s D_sᵀD_s, exactly
        p, c = f.stencils.particles, f.stencils.coeffs
        rows.append(np.repeat(p, 4, axis=1).ravel())
        cols.append(np.tile(p, (1, 4)).ravel())
        vals.append((k_stencil[:, None, None] * c[:, :, None] * c[:, None, :]).ravel())
    r = np.concatenate(rows)
    c = np.concatenate(cols)
    v = np.concatenate(vals)
    free = model.inv_mass > 0
    keep = free[r] & free[c]
    return sp.coo_matrix((v[keep], (r[keep], c[keep])), shape=(n, n)).tocsr()


def step_matrix(model, k_edge: np.ndarray, k_stencil: np.ndarray, h: float):
    """P (module docstring) as a SciPy CSR matrix, for `model`'s held particles now."""
    import scipy.sparse as sp

    free = model.inv_mass > 0
    diag = np.where(free, model.mass / (h * h), 1.0)
    return (stiffness_matrix(model, k_edge, k_stencil) + sp.diags(diag)).tocsr()


def bending_share(model, springs, k_stencil: np.ndarray) -> float:
    """Q_B's largest diagonal entry over the smallest of `springs` (K without Q_B) among the
    free particles that have a spring left (one whose springs all tore has no bending
    either), or 0 without stencils."""
    f = model.fabric
    if f is None or f.stencils is None or not len(k_stencil):
        return 0.0
    p, c = f.stencils.particles, f.stencils.coeffs
    bending = np.bincount(p.ravel(), weights=(k_stencil[:, None] * c * c).ravel(),
                          minlength=model.num_particles)
    diagonal = springs.diagonal()
    free = model.inv_mass > 0
    tied = free & (diagonal > 0)
    if not tied.any():
        return math.inf
    return float(bending[free].max() / diagonal[tied].min())


def preconditioner_stiffness(model, k_edge: np.ndarray, k_stencil: np.ndarray):
    """K for the V-cycle's P: without Q_B where its share is under BENDING_SHARE."""
    springs = stiffness_matrix(model, k_edge, None)
    if bending_share(model, springs, k_stencil) < BENDING_SHARE:
        return springs
    return stiffness_matrix(model, k_edge, k_stencil)


def kept_preconditioner(model, k_edge: np.ndarray, k_stencil: np.ndarray,
                        h: float) -> StepMultigrid:
    """P⁻¹'s V-cycle (multigrid.py) for `model`'s held particles now and substeps of h
    (without Q_B where it is small: `preconditioner_stiffness`), the same object again where
    one of the last KEPT was made from the same stiffness."""
    inputs = ((model.inv_mass == 0).tobytes(), k_edge.tobytes(), k_stencil.tobytes())
    _kept[:] = [entry for entry in _kept if entry[0]() is not None]  # (a sheet let go)
    for i, (ref, made_from, cycle) in enumerate(_kept):
        if ref() is model and made_from == inputs:
            # (moved by index: list.remove would compare the models, arrays and all)
            _kept.append(_kept.pop(i))
            break
    else:
        cycle = StepMultigrid(preconditioner_stiffness(model, k_edge, k_stencil), model.mass,
                              model.inv_mass == 0, model.nx, model.nz)
        _kept.append((weakref.ref(model), inputs, cycle))
        del _kept[:-KEPT]
    cycle.set_step(h)
    return cycle
