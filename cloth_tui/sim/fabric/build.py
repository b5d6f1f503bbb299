"""A scene's material on its model's grid: what the solver's constraints are made of.

With a `[material]` (materials/section.py) the model's distance constraints are the
structural edges alone, each with its own XPBD compliance α = 1/k from the fabric's stretch
and the strip of sheet the edge stands for (material.pair_compliance); shear is one
constraint per cell (material.cell_shear_strain, α = 1/(G·dx·dz)); bending is the grid
bending energy's stencils (bending.py), each a vector constraint C_s = D_s·x of compliance
1/(B·w_s); masses are the areal density × each particle's dual cell. A measured preset's
stretch stiffens with strain (stretch_curve.py: `stretch`, from which the solver makes each
edge's α anew every substep) and its stencils' B differ by kind, so that folds along the
warp, the bias and the weft have the measured rigidities (bending.stencil_rigidities).
xpbd/fabric_constraints.py projects the cells and stencils; docs/physics.md ("Materials in
SI units", "Measured fabrics: stiffening and direction") derives it all.
"""

from __future__ import annotations

from dataclasses import dataclass, replace

import numpy as np

from ...materials.schema import Material
from .bending import (Stencils, bending_stencils, directional_bending_compliance,
                      stencil_rigidities)
from ..grid import Grid
from .material import cell_shear_compliance, lumped_masses, pair_compliance
from .stretch_curve import EdgeStretch, edge_stretch


@dataclass(frozen=True)
class Fabric:
    material: Material
    grid: Grid
    compliance: np.ndarray          # (M,) m/N per distance constraint, model.edges order
    cells: np.ndarray               # (C, 4) int64 corners of each shear cell (none: (0, 4))
    cell_compliance: float          # 1/(N·m), the same for every cell
    stencils: Stencils | None       # bending stencils, None without bending
    stencil_compliance: np.ndarray  # (S,) 1/N per stencil (none: (0,))
    cell_edges: np.ndarray          # (C, 4) the structural constraints around each cell, −1 none
    stencil_edges: np.ndarray       # (S, 4) structural constraints a stencil spans, −1 none
    stretch: EdgeStretch | None = None  # tension curves per edge; None: linear (compliance)

    @property
    def num_cells(self) -> int:
        return len(self.cells)

    @property
    def num_stencils(self) -> int:
        return 0 if self.stencils is None else len(self.stencils.weights)

    @property
    def stencil_rigidity(self) -> np.ndarray:
        """(S,) N·m: each stencil's bending rigidity, 1/(α_s·w_s)."""
        if self.stencils is None:
            return np.zeros(0)
        return 1.0 / (self.stencil_compliance * self.stencils.weights)


def _stencil_compliance(stencils: Stencils | None, material: Material) -> np.ndarray:
    if stencils is None:
        return np.zeros(0)
    return directional_bending_compliance(
        stencils, stencil_rigidities(stencils, material.bending, material.bending_by_direction))


def fabric_masses(material: Material, grid: Grid) -> np.ndarray:
    """(N,) kg: areal density × dual cell; they sum to density × area."""
    return lumped_masses(grid, material.areal_density)


def build_fabric(material: Material, grid: Grid, edges: np.ndarray, shear: bool,
                 bending: bool) -> Fabric:
    """The fabric's constraints on `grid`: `edges` are the model's (structural only,
    any order); `shear` and `bending` say whether those families are on
    (behavior.shear, behavior.bending)."""
    compliance = pair_compliance(material, grid, edges, shear="cells")
    cells = grid.cell_corners() if shear else np.zeros((0, 4), np.int64)
    stencils = bending_stencils(grid) if bending and material.bending > 0 else None
    stencil_alpha = _stencil_compliance(stencils, material)
    edge_of = _edge_lookup(edges, grid.num_particles)
    cell_edges = np.stack([edge_of(cells[:, 0], cells[:, 1]), edge_of(cells[:, 2], cells[:, 3]),
                           edge_of(cells[:, 0], cells[:, 2]), edge_of(cells[:, 1], cells[:, 3])],
                          axis=1) if len(cells) else np.zeros((0, 4), np.int64)
    stencil_edges = _stencil_edges(stencils, edge_of) if stencils is not None \
        else np.zeros((0, 4), np.int64)
    for arr in (compliance, cells, stencil_alpha, cell_edges, stencil_edges):
        arr.setflags(write=False)
    return Fabric(material=material, grid=grid, compliance=compliance, cells=cells,
                  cell_compliance=cell_shear_compliance(material, grid), stencils=stencils,
                  stencil_compliance=stencil_alpha, cell_edges=cell_edges,
                  stencil_edges=stencil_edges, stretch=edge_stretch(material, grid, edges))


def refit_fabric(fabric: Fabric, material: Material, edges: np.ndarray) -> Fabric:
    """`fabric`'s constraints (on the model's `edges`) with `material`'s numbers: a material
    that leaves the constraints as they are (bending rigidity still above zero, or still
    none), whose α per constraint are made anew."""
    compliance = pair_compliance(material, fabric.grid, edges, shear="cells")
    stencil_alpha = (_stencil_compliance(fabric.stencils, material)
                     if fabric.stencils is not None else fabric.stencil_compliance)
    for arr in (compliance, stencil_alpha):
        arr.setflags(write=False)
    return replace(fabric, material=material, compliance=compliance,
                   cell_compliance=cell_shear_compliance(material, fabric.grid),
                   stencil_compliance=stencil_alpha,
                   stretch=edge_stretch(material, fabric.grid, edges))


def _edge_lookup(edges: np.ndarray, particles: int):
    """A function (a, b) → index of constraint a–b in `edges` (either order), −1 if none."""
    key = np.minimum(edges[:, 0], edges[:, 1]) * particles + np.maximum(edges[:, 0],
                                                                        edges[:, 1])
    order = np.argsort(key)
    sorted_key = key[order]

    def edge_of(a, b):
        k = np.minimum(a, b) * particles + np.maximum(a, b)
        if not len(sorted_key):
            return np.full(len(k), -1, np.int64)
        at = np.minimum(np.searchsorted(sorted_key, k), len(sorted_key) - 1)
        return np.where(sorted_key[at] == k, order[at], -1).astype(np.int64)

    return edge_of


def _stencil_edges(stencils: Stencils, edge_of) -> np.ndarray:
    """The structural constraints whose tearing ends a stencil: for x_uu and x_vv the two
    edges of its line (the other slots −1), for x_uv the four sides of its cell."""
    p = stencils.particles
    second = stencils.coeffs[:, 3] == 0.0  # x_uu, x_vv: particles (prev, mid, next, mid)
    out = np.full((len(p), 4), -1, np.int64)
    out[second, 0] = edge_of(p[second, 0], p[second, 1])
    out[second, 1] = edge_of(p[second, 1], p[second, 2])
    cross = ~second  # x_uv: (i, j), (i, j+1), (i+1, j), (i+1, j+1)
    out[cross, 0] = edge_of(p[cross, 0], p[cross, 1])
    out[cross, 1] = edge_of(p[cross, 2], p[cross, 3])
    out[cross, 2] = edge_of(p[cross, 0], p[cross, 2])
    out[cross, 3] = edge_of(p[cross, 1], p[cross, 3])
    return out
