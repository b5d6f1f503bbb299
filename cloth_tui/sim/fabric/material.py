"""A material (cloth_tui.materials: SI units) discretised on a regular grid of particles.

The grid is sim/grid.py's (nz rows of nx particles, spacings dz and dx, particle (row i,
column j) at index i·nx + j). Everything here
follows from the material and the rest geometry alone, so that the same fabric behaves the
same at every resolution (docs/physics.md, "Materials in SI units", derives each formula):

- lumped masses: areal density × the particle's dual cell;
- the membrane: XPBD compliance α = 1/k (m/N) per structural edge from the stretch
  stiffness and the strip of sheet the edge stands for, and shear either as diagonal springs
  (`shear="springs"`, today's distance-constraint kernel) or as one shear-strain constraint
  per cell (`shear="cells"`, any fabric, needs a kernel of its own);
- tearing's measure: the tension per unit width a structural edge's force stands for;
- damping: a decay rate in 1/s applied as a factor per substep, so it does not depend on
  the substep length.

Pure numpy: fabric/build.py turns these into the model's fabric.
"""

from __future__ import annotations

import math

import numpy as np

from ...materials.errors import MaterialError
from ...materials.schema import Material
from ..grid import Grid, grid_pairs

SHEAR_MODELS = ("cells", "springs")
# The schema accepts any positive density and stiffness, down to 5e-324. Below these a
# particle's 1/m, or a constraint's α = 1/k (and α/h² of the solve), would overflow to inf and
# the solve to NaN; at them the sheet is already weightless or limp for every scene.
MIN_MASS = 1e-30       # kg per particle
MIN_STIFFNESS = 1e-30  # N/m per edge, N·m per shear cell: α ≤ 1e30


def lumped_masses(grid: Grid, areal_density: float) -> np.ndarray:
    """(N,) kg: density × each particle's dual cell; they sum to density × area (each at
    least MIN_MASS)."""
    return np.maximum(areal_density * np.outer(grid.row_share(), grid.col_share()).ravel(),
                      MIN_MASS)


def diagonal_spring_stiffness(material: Material, grid: Grid) -> float:
    """N/m of each diagonal spring when the diagonals carry the shear: both diagonals of a
    cell together give the energy ½·G·γ²·(dx·dz) of a shear γ."""
    return material.shear * (grid.dx ** 2 + grid.dz ** 2) / (2 * grid.dx * grid.dz)


def structural_stiffness(material: Material, grid: Grid, shear: str = "cells") -> tuple:
    """(k_u per row, k_v per column), N/m: the stiffness of the edges along x in each row and
    along z in each column. An edge stands for the strip of sheet its row (column) covers, so
    k = stretch × strip width / edge length. With diagonal springs the diagonals also resist
    stretching (G·(dx/dz)² along x per unit area); the structural edges carry the rest."""
    if shear not in SHEAR_MODELS:
        raise ValueError(f"unknown shear model {shear!r}: one of {', '.join(SHEAR_MODELS)}")
    warp, weft = material.stretch_warp, material.stretch_weft
    if shear == "springs":
        along_x = material.shear * (grid.dx / grid.dz) ** 2
        along_z = material.shear * (grid.dz / grid.dx) ** 2
        if along_x >= warp or along_z >= weft:
            raise MaterialError(
                f"shear {material.shear:g} N/m on cells of {grid.dx:.3g}×{grid.dz:.3g} m needs "
                f"stretch above {along_x:.3g} N/m (warp) and {along_z:.3g} N/m (weft), got "
                f"{warp:g} and {weft:g}: diagonal springs cannot be that stiff in shear "
                "without stretching too; use cell shear constraints")
        warp, weft = warp - along_x, weft - along_z
    return warp * grid.row_share() / grid.dx, weft * grid.col_share() / grid.dz


ALONG_X, ALONG_Z, DIAGONAL, OTHER = 0, 1, 2, -1


def pair_kinds(grid: Grid, pairs: np.ndarray) -> tuple[np.ndarray, np.ndarray, np.ndarray]:
    """For (M, 2) pairs of particles in any order: each pair's kind (ALONG_X, ALONG_Z,
    DIAGONAL or OTHER) and the row and column of its lower particle."""
    pairs = np.asarray(pairs, dtype=np.int64).reshape(-1, 2)
    if len(pairs) and (pairs.min() < 0 or pairs.max() >= grid.num_particles):
        raise ValueError(f"pairs name particles outside the {grid.nz}×{grid.nx} grid")
    a, b = pairs.min(axis=1), pairs.max(axis=1)
    ia, ja = np.divmod(a, grid.nx)
    ib, jb = np.divmod(b, grid.nx)
    di, dj = ib - ia, jb - ja
    kind = np.full(len(pairs), OTHER, dtype=np.int8)
    kind[(di == 0) & (dj == 1)] = ALONG_X
    kind[(di == 1) & (dj == 0)] = ALONG_Z
    kind[(di == 1) & (np.abs(dj) == 1)] = DIAGONAL
    return kind, ia, ja


def _refuse(pairs, kind, allowed, grid: Grid) -> None:
    bad = ~np.isin(kind, allowed)
    if bad.any():
        e = int(np.flatnonzero(bad)[0])
        what = ("a diagonal (shear is in the cells)" if kind[e] == DIAGONAL
                else "not a neighbour pair")
        raise ValueError(f"pair {tuple(int(p) for p in np.asarray(pairs)[e])} of a "
                         f"{grid.nz}×{grid.nx} grid is {what}")


def strip_width(grid: Grid, pairs: np.ndarray) -> np.ndarray:
    """(M,) m: the width of sheet each structural pair stands for, across its direction
    (its row's height for an edge along x, its column's width along z; half on a border)."""
    kind, i, j = pair_kinds(grid, pairs)
    _refuse(pairs, kind, (ALONG_X, ALONG_Z), grid)
    return np.where(kind == ALONG_X, grid.row_share()[i], grid.col_share()[j])


def tension_per_width(force: np.ndarray, grid: Grid, pairs: np.ndarray) -> np.ndarray:
    """(M,) N/m: the tension per unit width that structural pairs carrying `force` (N) stand
    for, what tear_strength is compared with."""
    return np.asarray(force, dtype=float) / strip_width(grid, pairs)


def pair_stiffness(material: Material, grid: Grid, pairs: np.ndarray,
                   shear: str = "cells") -> np.ndarray:
    """(M,) N/m for any (M, 2) array of neighbour pairs of the grid, in any order (such as a
    model's colour-sorted edges). Diagonal pairs are springs only with shear="springs"; any
    other pair (two apart: the distance "bending" family) has no place in a material."""
    k_u, k_v = structural_stiffness(material, grid, shear)
    kind, i, j = pair_kinds(grid, pairs)
    _refuse(pairs, kind, (ALONG_X, ALONG_Z, DIAGONAL) if shear == "springs"
            else (ALONG_X, ALONG_Z), grid)
    out = np.where(kind == ALONG_X, k_u[i], k_v[j])
    return np.where(kind == DIAGONAL, diagonal_spring_stiffness(material, grid), out)


def pair_compliance(material: Material, grid: Grid, pairs: np.ndarray,
                    shear: str = "cells") -> np.ndarray:
    """(M,) m/N: XPBD's α = 1/k per pair (the kernel divides by h² itself), k at least
    MIN_STIFFNESS."""
    return 1.0 / np.maximum(pair_stiffness(material, grid, pairs, shear), MIN_STIFFNESS)


def cell_shear_strain(x: np.ndarray, grid: Grid) -> np.ndarray:
    """(C,) the shear γ of each cell: (|d₁|² − |d₂|²)/(4·dx·dz) with d₁, d₂ its diagonals.
    It is 2·E_xz of the Green strain (γ for a small shear) and exactly 0 however the cell is
    stretched along x or z, so it adds no stiffness to stretching."""
    c = grid.cell_corners()
    d1 = x[c[:, 3]] - x[c[:, 0]]
    d2 = x[c[:, 2]] - x[c[:, 1]]
    return ((d1 * d1).sum(axis=1) - (d2 * d2).sum(axis=1)) / (4 * grid.dx * grid.dz)


def cell_shear_compliance(material: Material, grid: Grid) -> float:
    """1/(N·m): α of each cell's constraint C = γ, whose energy C²/(2α) = ½·G·γ²·dx·dz
    (G·dx·dz at least MIN_STIFFNESS)."""
    return 1.0 / max(material.shear * grid.dx * grid.dz, MIN_STIFFNESS)


def membrane_energy(x: np.ndarray, material: Material, grid: Grid,
                    shear: str = "cells") -> float:
    """J: the elastic energy of positions x (N, 3) under the per-edge (and per-cell)
    compliances above: Σ C²/(2α) with C = |x_b − x_a| − L₀ per spring, C = γ per cell."""
    rest = grid.rest_positions()
    pairs = grid_pairs(grid)
    kinds = ("u", "v", "diagonal") if shear == "springs" else ("u", "v")
    energy = 0.0
    for kind in kinds:
        p = pairs[kind]
        alpha = pair_compliance(material, grid, p, shear)
        length = np.linalg.norm(x[p[:, 1]] - x[p[:, 0]], axis=1)
        rest_length = np.linalg.norm(rest[p[:, 1]] - rest[p[:, 0]], axis=1)
        energy += float(((length - rest_length) ** 2 / (2 * alpha)).sum())
    if shear == "cells":
        energy += float((cell_shear_strain(x, grid) ** 2).sum()
                        / (2 * cell_shear_compliance(material, grid)))
    return energy


def damping_factor(rate: float, h: float) -> float:
    """The factor on velocities for one substep of h seconds under a damping `rate` (1/s):
    exp(−rate·h), so n substeps of h/n damp exactly as one of h."""
    return math.exp(-rate * h)


def damping_rate_from_share(share: float, interval: float) -> float:
    """The rate (1/s) that loses `share` of the velocity every `interval` seconds (such as
    behavior.damping's share per 18 ms): −ln(1 − share)/interval."""
    if not 0.0 <= share < 1.0:
        raise ValueError(f"a share of velocity lost must be in [0, 1), got {share}")
    return -math.log1p(-share) / interval
