"""Tearing: constraints that break, by their load or by a cut, and leave the solve for good.

The model's constraints do not change; the state keeps which are intact (`state.alive`, 1 or 0 per
constraint in model.edges order) and how many are broken (`state.torn`, counted by `_record_breaks`
alone). Every solver skips a broken constraint (xpbd/constraints.py, springs/integrators.py,
springs/implicit_euler.py), the measures leave it out (measures.py), a material's shear cells and
bending stencils across a broken edge leave with it (xpbd/fabric_constraints.py), and the renderer
drops the triangles that lost an edge (`intact_triangles`).

Break criterion, checked once per substep after the constraint solve, in tension only:

- by strength (`TearByStrength`: a scene's [material] with tear_strength, a solver that
  keeps multipliers): a structural edge breaks when the tension per unit width around it,
  averaged across its direction over the fabric's tear_length ℓ, exceeds tear_strength,

      Σ_k o_k t_k / Σ_k o_k  >  tear_strength   →   alive = 0,    t_k = −λ_k/h² / w_k

  with λ_k the multiplier of the substep of an intact edge parallel to it in the band of
  width ℓ centred on it (tension makes it negative: xpbd/constraints.py), w_k the strip of
  sheet it stands for (material.strip_width) and o_k how much of that strip lies in the
  band. On a grid coarser than ℓ the band is the edge's own strip and this is its own
  tension. Where the tension is singular (the end of a clamped line) a single edge's grows
  without bound as the grid refines, so a per-edge criterion tears ever earlier; the mean
  over ℓ converges once the grid resolves ℓ (`strength_bands`). λ/h² is the force the
  constraint exerted in the substep, not its stretch read through the stiffness: a solve
  left short of convergence (few substeps, few passes) stretches the sheet further than the
  material would, but what it pushes with still balances the load, so the same load breaks
  the same edges at any substep count;
- by stretch (`TearConstraints`: without a material, or a material without tear_strength):

      L/L0 − 1 > tear_stretch   →   alive = 0

  (compared squared, L² > ((1 + tear_stretch) L0)², with no square root).

Compression breaks nothing: a fold squeezes a constraint to nearly zero length, and cloth
does not tear where it folds.

A cut (the app's right-drag) breaks every constraint whose segment, in the sheet's material
coordinates (row i, column j), crosses the cut's segment. Nothing is ever mended within a run:
a restart builds a new state with every constraint intact.
"""

from __future__ import annotations

import math

import numpy as np

from ...materials.schema import stiffness_at_tension
from ..jit import kernel
from ..fabric.material import ALONG_X, pair_kinds, strip_width
from ..grid import Grid
from ..model import ClothModel
from ..state import ClothState

# Tearing by strength asks the solve for the fabric's tension to this share of tear_strength:
# the force estimates λ/h² and k·(L − L0) differ by the stretch modulus × the solve error
# (module docstring), so the error is bounded by this share of the breaking strain.
TEAR_FORCE_SHARE = 0.1

# A cut runs through the picked particles, nudged off the grid's lines by this (in spacings)
# so that it never passes exactly through a particle, where it would cut ambiguously.
CUT_OFFSET = (1.3e-3, 2.9e-3)


@kernel()
def break_overstretched_constraints(x, edges, rest, alive, tear_stretch) -> int:
    """alive[e] = 0 for every intact constraint stretched beyond tear_stretch; returns how
    many broke. A NaN length breaks nothing here: the runner's guard sees the NaN state."""
    broken = 0
    limit = (1.0 + tear_stretch) * (1.0 + tear_stretch)
    for e in range(edges.shape[0]):
        if not alive[e]:
            continue
        a = edges[e, 0]
        b = edges[e, 1]
        dx = x[b, 0] - x[a, 0]
        dy = x[b, 1] - x[a, 1]
        dz = x[b, 2] - x[a, 2]
        if dx * dx + dy * dy + dz * dz > limit * rest[e] * rest[e]:
            alive[e] = 0
            broken += 1
    return broken


@kernel()
def break_overloaded_bands(lambdas, width, alive, h2, band_offsets, band_edges, band_overlap,
                           strength, mean) -> int:
    """alive[e] = 0 for every intact constraint whose band's mean tension per unit width
    (module docstring) exceeds `strength` (N/m); `mean` is scratch of one per constraint.
    The means are all taken before any edge breaks, so the order of the edges changes
    nothing. A NaN λ breaks nothing (the runner's guard sees the NaN state)."""
    for e in range(lambdas.shape[0]):
        mean[e] = 0.0
        if not alive[e]:
            continue
        total = 0.0
        weight = 0.0
        for k in range(band_offsets[e], band_offsets[e + 1]):
            n = band_edges[k]
            if alive[n]:
                total += band_overlap[k] * (-lambdas[n] / (h2 * width[n]))
                weight += band_overlap[k]
        mean[e] = total / weight
    broken = 0
    for e in range(lambdas.shape[0]):
        if alive[e] and mean[e] > strength:
            alive[e] = 0
            broken += 1
    return broken


def strength_bands(grid: Grid, edges: np.ndarray, tear_length: float
                   ) -> tuple[np.ndarray, np.ndarray, np.ndarray]:
    """Each structural edge's band (module docstring) as (offsets (M+1,), edges, overlaps
    in m): the edges parallel to it whose strips meet the band of width `tear_length`
    centred on it, across its direction, with how much of each strip lies in the band.
    An edge's own strip always does, so every band holds its edge."""
    kind, i, j = pair_kinds(grid, edges)
    m = len(edges)
    along_x = kind == ALONG_X
    # across an edge along x lie the rows (spacing dz); across one along z, the columns
    across = np.where(along_x, i, j)
    spacing = np.where(along_x, grid.dz, grid.dx)
    count = np.where(along_x, grid.nz, grid.nx)
    lookup = np.full((2,) + grid.shape, -1, np.int64)
    lookup[along_x.astype(np.int64), i, j] = np.arange(m)
    reach = int(math.ceil(tear_length / (2.0 * min(grid.dx, grid.dz)))) + 1
    owners, members, overlaps = [], [], []
    for k in range(-reach, reach + 1):
        line = across + k
        inside = (line >= 0) & (line < count)
        e = np.flatnonzero(inside)
        row = np.where(along_x[e], line[e], i[e])
        col = np.where(along_x[e], j[e], line[e])
        neighbour = lookup[along_x[e].astype(np.int64), row, col]
        # the neighbour's strip, relative to the edge's line: half a spacing each side, none
        # beyond the sheet's border
        h = spacing[e]
        lo = k * h - np.where(line[e] > 0, h / 2, 0.0)
        hi = k * h + np.where(line[e] < count[e] - 1, h / 2, 0.0)
        overlap = np.minimum(hi, tear_length / 2) - np.maximum(lo, -tear_length / 2)
        if k == 0:  # the edge's own strip, however narrow the band (alone, any weight)
            overlap = np.where(overlap > 0.0, overlap, 1.0)
        keep = (neighbour >= 0) & (overlap > 0.0)
        owners.append(e[keep])
        members.append(neighbour[keep])
        overlaps.append(overlap[keep])
    owner = np.concatenate(owners)
    order = np.argsort(owner, kind="stable")
    offsets = np.zeros(m + 1, np.int64)
    np.cumsum(np.bincount(owner, minlength=m), out=offsets[1:])
    return (offsets, np.ascontiguousarray(np.concatenate(members)[order]),
            np.ascontiguousarray(np.concatenate(overlaps)[order]))


@kernel(inline="always")
def _side(ax, ay, bx, by, px, py) -> float:
    """> 0 when p is left of the line a→b, < 0 right of it (twice the signed area)."""
    return (bx - ax) * (py - ay) - (by - ay) * (px - ax)


@kernel()
def cut_constraints(edges, nx, alive, i0, j0, i1, j1) -> int:
    """alive[e] = 0 for every intact constraint whose segment in grid coordinates (i, j) of
    a grid nx particles wide properly crosses the cut (i0, j0)–(i1, j1); returns how many
    were cut."""
    cut = 0
    for e in range(edges.shape[0]):
        if not alive[e]:
            continue
        a = edges[e, 0]
        b = edges[e, 1]
        ai, aj = float(a // nx), float(a % nx)
        bi, bj = float(b // nx), float(b % nx)
        if (_side(i0, j0, i1, j1, ai, aj) * _side(i0, j0, i1, j1, bi, bj) < 0.0
                and _side(ai, aj, bi, bj, i0, j0) * _side(ai, aj, bi, bj, i1, j1) < 0.0):
            alive[e] = 0
            cut += 1
    return cut


def tear_strength(behavior, model: ClothModel) -> float | None:
    """N/m: the strength the sheet tears at, where it tears by strength (behavior.tear and
    a material with tear_strength); None where it tears by stretch or not at all."""
    fabric = model.fabric
    if not behavior.tear or fabric is None or not model.num_constraints:
        return None
    return fabric.material.tear_strength


def strength_tolerance(model: ClothModel, strength: float) -> float:
    """The solve error (share of rest length) that knows every edge's tension to within
    TEAR_FORCE_SHARE of `strength`: that share of `strength` over the stiffer direction's
    stiffness where it pulls with `strength` (a measured preset's tension curve is steeper
    there than at rest)."""
    return TEAR_FORCE_SHARE * strength / stiffness_at_tension(model.fabric.material, strength)


def _record_breaks(state: ClothState, count: int) -> int:
    """The one place the torn count grows: every break, by load or by a cut, comes here."""
    state.torn += count
    return count


def remove_constraints(state: ClothState, which: np.ndarray) -> int:
    """Take the constraints `which` (a mask) selects out of the solve, as a tear does;
    returns how many were still intact."""
    newly = np.asarray(which, dtype=bool) & (state.alive != 0)
    state.alive[newly] = 0
    return _record_breaks(state, int(np.count_nonzero(newly)))


def cut_between(model: ClothModel, state: ClothState, p0: int, p1: int) -> int:
    """Cut the sheet along the material path from particle p0 to particle p1; returns the
    constraints cut. The same particle twice cuts nothing."""
    nx = model.nx
    (i0, j0), (i1, j1) = divmod(int(p0), nx), divmod(int(p1), nx)
    di, dj = float(i1 - i0), float(j1 - j0)
    length = math.hypot(di, dj)
    if length == 0.0 or not model.num_constraints:
        return 0
    # Half a spacing more at both ends: the cuts of one drag overlap, and a cut from a
    # border particle reaches the border.
    ext = 0.5 / length
    oi, oj = CUT_OFFSET
    return _record_breaks(state, int(cut_constraints(model.edges, nx, state.alive,
                                                     i0 + oi - ext * di, j0 + oj - ext * dj,
                                                     i1 + oi + ext * di, j1 + oj + ext * dj)))


def triangle_constraints(model: ClothModel) -> np.ndarray:
    """(T, 3) int64: for each of model.triangles' three edges, the index of the constraint
    along it, or −1 where no constraint is (a family turned off)."""
    n2 = model.num_particles
    e = model.edges
    keys = np.minimum(e[:, 0], e[:, 1]) * n2 + np.maximum(e[:, 0], e[:, 1])
    order = np.argsort(keys)
    sorted_keys = keys[order]
    tri = model.triangles
    out = np.full(tri.shape, -1, np.int64)
    for k, (u, w) in enumerate(((0, 1), (1, 2), (2, 0))):
        q = np.minimum(tri[:, u], tri[:, w]) * n2 + np.maximum(tri[:, u], tri[:, w])
        pos = np.clip(np.searchsorted(sorted_keys, q), 0, max(len(keys) - 1, 0))
        if len(keys):
            hit = sorted_keys[pos] == q
            out[hit, k] = order[pos[hit]]
    return out


def intact_triangles(model: ClothModel, alive: np.ndarray,
                     edge_index: np.ndarray | None = None) -> np.ndarray:
    """The model's triangles none of whose edges' constraints is torn: torn edges show as a
    gap, not as a stretched face. `edge_index` is triangle_constraints(model), if at hand."""
    idx = triangle_constraints(model) if edge_index is None else edge_index
    ok = np.ones(len(idx), bool)
    for k in range(3):
        has = idx[:, k] >= 0
        ok[has] &= alive[idx[has, k]].astype(bool)
    return model.triangles[ok]


class TearConstraints:
    """The tearing stage by stretch: after the constraint solve, constraints stretched beyond
    behavior.tear_stretch break (see the module's docstring)."""

    name = "tear_constraints"

    def __init__(self, model: ClothModel, tear_stretch: float):
        self.model = model
        self.tear_stretch = float(tear_stretch)

    def apply(self, state: ClothState, h: float) -> None:
        m = self.model
        _record_breaks(state, int(break_overstretched_constraints(
            state.x, m.edges, m.rest_length, state.alive, self.tear_stretch)))


class TearByStrength:
    """The tearing stage by strength: after the constraint solve, structural edges whose
    tension per unit width, averaged over the fabric's tear_length across them, exceeds its
    tear_strength break (module docstring). `lambdas` is the projection's live array of the
    substep's multipliers (model.edges order), read after every solve."""

    name = "tear_by_strength"

    def __init__(self, model: ClothModel, lambdas: np.ndarray, tear_strength: float,
                 tear_length: float = 0.0):
        self.model = model
        self.lambdas = lambdas
        self.tear_strength = float(tear_strength)
        grid = Grid.of_model(model)
        self.width = np.ascontiguousarray(strip_width(grid, model.edges))
        self.bands = strength_bands(grid, model.edges, float(tear_length))
        self._mean = np.zeros(len(model.edges))

    def apply(self, state: ClothState, h: float) -> None:
        _record_breaks(state, int(break_overloaded_bands(
            self.lambdas, self.width, state.alive, h * h, *self.bands, self.tear_strength,
            self._mean)))
