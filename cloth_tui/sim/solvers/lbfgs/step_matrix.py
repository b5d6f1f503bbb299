"""The constant matrix P = M/h² + Σ_edges k_e A_eᵀA_e + Σ_cells w_c (diagonals) + Q_B, one
N×N matrix for x, y and z alike, and the V-cycle that stands for its inverse (multigrid.py),
made once per pin set and stiffness and kept for a step made again with the same
(`kept_preconditioner`); a new substep length h only adds M/h² again.

It is the Hessian of the step's objective (step_energy.py) with every edge held at its rest
length and no geometric stiffness: exact for the bending energy (linear stencils: Q_B is its
Hessian), the stretch and shear as springs along their lines. L-BFGS
starts each step from P⁻¹ and learns what it misses (the sheet's turning) from its
gradients. A held particle's row and column are the identity, so it never moves."""

from __future__ import annotations

import weakref

import numpy as np

from .multigrid import StepMultigrid

# V-cycles kept for steps made again: the accuracy control and the guard build a new step at
# each change of the substeps, and a frame redone from before a tear goes back to the
# stiffness it had (a large sheet's coarse grids take a visible moment to make).
KEPT = 2
_kept: list = []  # (model's weak reference, the stiffness's inputs, V-cycle), the latest last


def shear_weight(fabric) -> float:
    """N/m: a shear cell's energy k_c γ²/2 on each of its diagonals as a spring, the
    Gauss-Newton weight k_c |∂γ/∂d|² = k_c (2·scale·|d|)² at rest."""
    g = fabric.grid
    scale = 1.0 / (4 * g.dx * g.dz)
    return 4 * scale * scale * (g.dx * g.dx + g.dz * g.dz) / fabric.cell_compliance


def stiffness_matrix(model, k_edge: np.ndarray, k_stencil: np.ndarray):
    """K = Σ_edges k_e A_eᵀA_e + Σ_cells w_c (diagonals) + Q_B as a SciPy CSR matrix, its
    held particles' rows and columns empty; `k_stencil` = 1/α_s per bending stencil (its
    rigidity × weight, by direction)."""
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


def kept_preconditioner(model, k_edge: np.ndarray, k_stencil: np.ndarray,
                        h: float) -> StepMultigrid:
    """P⁻¹'s V-cycle (multigrid.py) for `model`'s held particles now and substeps of h, the
    same object again where one of the last KEPT was made from the same stiffness."""
    inputs = ((model.inv_mass == 0).tobytes(), k_edge.tobytes(), k_stencil.tobytes())
    _kept[:] = [entry for entry in _kept if entry[0]() is not None]  # (a sheet let go)
    for i, (ref, made_from, cycle) in enumerate(_kept):
        if ref() is model and made_from == inputs:
            # (moved by index: list.remove would compare the models, arrays and all)
            _kept.append(_kept.pop(i))
            break
    else:
        cycle = StepMultigrid(stiffness_matrix(model, k_edge, k_stencil), model.mass,
                              model.inv_mass == 0, model.nx, model.nz)
        _kept.append((weakref.ref(model), inputs, cycle))
        del _kept[:-KEPT]
    cycle.set_step(h)
    return cycle
