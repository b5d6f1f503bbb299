"""A bending energy native to the grid: B/2 times the squared second derivatives of the
positions, E = (B/2) ∫ (|x_uu|² + 2|x_uv|² + |x_vv|²) dA, in finite differences.

For a deformation that does not stretch the sheet (cloth bends, it barely stretches) the
second derivatives are normal to the surface and equal the second fundamental form, so the
integrand is κ₁² + κ₂²: the plate energy (B/2)∫κ² dA of a bending rigidity B, in every
direction alike (docs/physics.md, "Bending", derives it and its isotropy). Each stencil is a
linear function of the positions, so the energy is quadratic, E = ½ xᵀQx per coordinate,
with a constant Hessian Q; an affine map of the flat sheet (any rigid motion) costs nothing.

Stencils, each a 3-vector D_s·x with a weight w_s (m²):
- x_uu at each particle with a left and a right neighbour: (x_{j−1} − 2x_j + x_{j+1})/dx²;
- x_vv likewise along the columns, with dz;
- x_uv on each cell: (x_{i+1,j+1} − x_{i+1,j} − x_{i,j+1} + x_{i,j})/(dx·dz), counted twice.
A stencil's weight is the area whose curvature it stands for: its particle's dual cell, and
for a stencil next to a border also the half-cell strip beyond it, which has no stencil of
its own; so a uniform curvature's energy is exact up to the border. A clamp therefore holds
three columns, not two: the hinge at its edge must not be a border stencil (measured in
tests/sim/fabric/test_bending_cantilever.py).

Pure numpy: fabric/build.py builds a material's stencils, which the solvers project.
"""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np

from ..grid import Grid
from .material import MIN_STIFFNESS


@dataclass(frozen=True)
class Stencils:
    particles: np.ndarray   # (S, 4) int64; unused slots repeat a particle with coefficient 0
    coeffs: np.ndarray      # (S, 4) 1/m²
    weights: np.ndarray     # (S,) m²

    def apply(self, x: np.ndarray) -> np.ndarray:
        """(S, 3): D_s·x for every stencil."""
        return np.einsum("sk,skc->sc", self.coeffs, x[self.particles])


def _second_difference_weights(count: int, spacing: float) -> np.ndarray:
    """Widths (m) of the centred second differences at positions 1 … count−2 of a line of
    `count` particles: one spacing each, plus the half spacing beyond the first and last."""
    w = np.full(count - 2, spacing)
    w[0] += spacing / 2
    w[-1] += spacing / 2
    return w


def bending_stencils(grid: Grid) -> Stencils:
    """Every second-derivative stencil of the grid with its weight: built once per grid
    (the energy's Hessian is constant)."""
    idx = np.arange(grid.num_particles).reshape(grid.shape)
    rows_w, cols_w = grid.row_share(), grid.col_share()
    parts, coeffs, weights = [], [], []
    if grid.nx >= 3:  # x_uu along each row
        p = np.stack([idx[:, :-2], idx[:, 1:-1], idx[:, 2:], idx[:, 1:-1]], axis=-1)
        c = np.array([1.0, -2.0, 1.0, 0.0]) / grid.dx ** 2
        w = np.outer(rows_w, _second_difference_weights(grid.nx, grid.dx))
        parts.append(p.reshape(-1, 4))
        coeffs.append(np.broadcast_to(c, (p.shape[0] * p.shape[1], 4)))
        weights.append(w.ravel())
    if grid.nz >= 3:  # x_vv along each column
        p = np.stack([idx[:-2, :], idx[1:-1, :], idx[2:, :], idx[1:-1, :]], axis=-1)
        c = np.array([1.0, -2.0, 1.0, 0.0]) / grid.dz ** 2
        w = np.outer(_second_difference_weights(grid.nz, grid.dz), cols_w)
        parts.append(p.reshape(-1, 4))
        coeffs.append(np.broadcast_to(c, (p.shape[0] * p.shape[1], 4)))
        weights.append(w.ravel())
    # x_uv on each cell, whose area is exactly dx·dz; twice, as x_uv = x_vu
    p = np.stack([idx[:-1, :-1], idx[:-1, 1:], idx[1:, :-1], idx[1:, 1:]], axis=-1)
    c = np.array([1.0, -1.0, -1.0, 1.0]) / (grid.dx * grid.dz)
    parts.append(p.reshape(-1, 4))
    coeffs.append(np.broadcast_to(c, (p.shape[0] * p.shape[1], 4)))
    weights.append(np.full(p.shape[0] * p.shape[1], 2 * grid.dx * grid.dz))
    return Stencils(particles=np.concatenate(parts).astype(np.int64),
                    coeffs=np.ascontiguousarray(np.concatenate(coeffs)),
                    weights=np.concatenate(weights))


def bending_energy(x: np.ndarray, stencils: Stencils, rigidity: float) -> float:
    """J: (B/2) Σ_s w_s |D_s·x|² for positions x (N, 3) and bending rigidity B (N·m)."""
    d = stencils.apply(x)
    return 0.5 * rigidity * float((stencils.weights * (d * d).sum(axis=1)).sum())


def bending_gradient(x: np.ndarray, stencils: Stencils, rigidity: float) -> np.ndarray:
    """(N, 3) N: ∂E/∂x = B Σ_s w_s D_sᵀ(D_s·x) (= Q x); the force is its negative."""
    d = stencils.apply(x) * (rigidity * stencils.weights)[:, None]
    grad = np.zeros_like(x, dtype=float)
    contrib = stencils.coeffs[:, :, None] * d[:, None, :]
    np.add.at(grad, stencils.particles.ravel(), contrib.reshape(-1, 3))
    return grad


def bending_hessian(stencils: Stencils, rigidity: float, num_particles: int) -> tuple:
    """The constant Hessian Q (N×N, the same for x, y and z) as COO triplets (rows, cols,
    values), duplicates summed: Q = B Σ_s w_s D_sᵀD_s. Symmetric positive semi-definite."""
    c = stencils.coeffs
    vals = (rigidity * stencils.weights)[:, None, None] * c[:, :, None] * c[:, None, :]
    r = np.broadcast_to(stencils.particles[:, :, None], vals.shape).ravel()
    k = np.broadcast_to(stencils.particles[:, None, :], vals.shape).ravel()
    key = r * num_particles + k
    keys, inverse = np.unique(key, return_inverse=True)
    summed = np.bincount(inverse, weights=vals.ravel())
    keep = summed != 0.0
    keys, summed = keys[keep], summed[keep]
    return keys // num_particles, keys % num_particles, summed


def bending_compliance(stencils: Stencils, rigidity: float) -> np.ndarray:
    """(S,) per stencil: the XPBD compliance of its vector constraint C_s = D_s·x (1/m), whose
    energy |C_s|²/(2α_s) is the stencil's share of the bending energy: α_s = 1/(B·w_s).
    The constraint is linear in x, so its gradient is the constant coefficient row. A sheet
    without bending rigidity has no bending constraints at all, rather than infinite α; a
    rigidity so small that B·w_s is below MIN_STIFFNESS counts as that (α stays finite)."""
    if not rigidity > 0:
        raise ValueError(f"bending constraints need a positive rigidity, got {rigidity}")
    return 1.0 / np.maximum(rigidity * stencils.weights, MIN_STIFFNESS)


UU, VV, UV = 0, 1, 2  # a stencil's kind: x_uu (curvature along x), x_vv (along z), x_uv


def stencil_kinds(stencils: Stencils) -> np.ndarray:
    """(S,) int8: UU, VV or UV per stencil (x_uu's middle particle is its first's right
    neighbour; x_vv's is a row further; x_uv has four non-zero coefficients)."""
    p = stencils.particles
    kind = np.where(p[:, 1] - p[:, 0] == 1, UU, VV).astype(np.int8)
    kind[stencils.coeffs[:, 3] != 0.0] = UV
    return kind


def stencil_rigidities(stencils: Stencils, rigidity: float, directions=None) -> np.ndarray:
    """(S,) N·m per stencil: `rigidity` for all, or with `directions`
    (materials.measured.BendingByDirection) the rigidity of its kind, so that folds at 0°,
    45° and 90° to the warp have the three measured rigidities (docs/physics.md, "Measured
    fabrics: stiffening and direction")."""
    if directions is None:
        return np.full(len(stencils.weights), float(rigidity))
    return np.asarray(directions.grid_rigidities())[stencil_kinds(stencils)]


def directional_bending_compliance(stencils: Stencils, rigidities: np.ndarray) -> np.ndarray:
    """(S,) per stencil: α_s = 1/(B_s·w_s) with a rigidity of its own (stencil_rigidities),
    as bending_compliance with one."""
    if not (np.asarray(rigidities) > 0).all():
        raise ValueError("bending constraints need positive rigidities")
    return 1.0 / np.maximum(rigidities * stencils.weights, MIN_STIFFNESS)
