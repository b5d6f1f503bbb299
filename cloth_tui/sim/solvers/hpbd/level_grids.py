"""The coarse levels of hierarchical PBD (after Müller 2008, "Hierarchical position based
dynamics"): nested grids over the sheet, their constraints, and how positions pass between a
level and the next finer one. Plain NumPy, built once per model; position_levels.py runs
them.

Level l (1, 2, ...) has a node at every row and column that is a multiple of 2^l counted from
either end of the sheet, up to its middle (`axis_nodes`), so every level spans the whole
sheet and lies on it symmetrically. Between a level and the next
finer one (the sheet itself, for level 1) positions pass both ways by the same bilinear
weights in the grid's indices: down by interpolation, up by full weighting (each node the
weighted mean of the finer particles around it). A mean, not the node's own particle:
a node that took its particle's position would read the fine sheet's short ripples as a
coarse stretch and spread a smooth correction where there was none (measured: the sheet
then gains energy at 16 substeps a frame).

Its constraints join level neighbours along rows and columns and across each cell's two
diagonals, at their distance on the flat sheet so restricted. They are one-sided: a coarse
constraint only stops its two nodes from getting farther apart than that, never closer,
since the fine sheet between them may fold or curve (a drape) and so shortens the chord.
A node's mass is the finer masses it takes by the weights (they sum to the sheet's mass),
and it is pinned where its own particle is: it then stands where that particle is, not at
the mean (which sags with the sheet around the pin and would hold the level from a point
the pin is not at).

Tearing: a coarse constraint or an interpolation cell whose box of fine particles touches a
torn constraint is left out (`torn_flags`), so no coarse level holds a cut together.
"""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np

from ...model import SHEAR, STRUCTURAL, ClothModel

MIN_NODES = 3  # a level needs at least this many rows and columns


@dataclass(frozen=True)
class Level:
    """One coarse level. Its nodes are indexed row by row ("local"); so are the particles
    of the finer level below it (the sheet's own, for level 1)."""

    nz: int                  # node rows and columns (grid.Grid's names): n = nz × nx
    nx: int
    nodes: np.ndarray        # (n,) int64: the fine particle at each node
    inv_mass: np.ndarray     # (n,) 1/kg of each node, 0 where pinned
    edges: np.ndarray        # (m, 2) int64 local node pairs, in conflict-free colour order
    color_offsets: np.ndarray  # (C+1,) int64
    rest: np.ndarray         # (m,) m: distance of each pair on the restricted flat sheet
    edge_box: np.ndarray     # (m, 4) int64: fine rows lo, hi and columns lo, hi each spans
    sources: np.ndarray      # (k, 4) int64: for each finer particle, its four nodes
    weights: np.ndarray      # (k, 4) bilinear weights
    own: np.ndarray          # (n,) int64: each node's own particle in the finer level
    free: np.ndarray         # (k,) uint8: 1 where the finer particle may move (not pinned)
    target_box: np.ndarray   # (k, 4) int64: the fine box of each finer particle's nodes


def axis_nodes(count: int, step: int) -> np.ndarray:
    """Indices 0 … count − 1 at multiples of `step` counted from both ends, each end's up to
    the middle: the nodes lie symmetrically, as the sheet does, with an odd interval (if any)
    in the middle. Each level's nodes are among the finer level's.

    Counted from the first index only, with the last one added, a short last interval made
    one side differ from the other: one particle long at 26², the level's last node was its
    particle alone and its constraint nearly a fine one, and the draped box's hanging edge
    never came to rest (0.015 m/s after 10 s). Merging that interval into the one before
    (3 long) tented a 16² sheet dropped on a post 3 cm over its cap, against pbd's 1.3."""
    half = np.arange(0, count, step)
    half = half[2 * half <= count - 1]
    return np.unique(np.concatenate([half, count - 1 - half])).astype(np.int64)


def _bracket(coarse: np.ndarray, fine: np.ndarray):
    """For each fine index: the coarse interval [k, k+1] it lies in and its weight on k+1."""
    k = np.clip(np.searchsorted(coarse, fine, side="right") - 1, 0, len(coarse) - 2)
    t = (fine - coarse[k]) / (coarse[k + 1] - coarse[k])
    return k, t


def _level_edges(rows: int, cols: int, structural: bool, shear: bool):
    """Local pairs of a rows × cols grid in 8 conflict-free colours: along rows and along
    columns by the parity of the column or row, each diagonal by the parity of the row."""
    idx = np.arange(rows * cols).reshape(rows, cols)
    groups = []
    if structural:
        for p in (0, 1):
            groups.append((idx[:, p:-1:2], idx[:, p + 1::2]))   # along a row
        for p in (0, 1):
            groups.append((idx[p:-1:2, :], idx[p + 1::2, :]))   # along a column
    if shear:
        for p in (0, 1):
            groups.append((idx[p:-1:2, :-1], idx[p + 1::2, 1:]))  # (i, j)–(i+1, j+1)
        for p in (0, 1):
            groups.append((idx[p:-1:2, 1:], idx[p + 1::2, :-1]))  # (i, j+1)–(i+1, j)
    pairs = [np.stack([a.ravel(), b.ravel()], axis=1) for a, b in groups if a.size]
    offsets = np.cumsum([0] + [len(p) for p in pairs]).astype(np.int64)
    edges = np.concatenate(pairs) if pairs else np.zeros((0, 2), np.int64)
    return edges.astype(np.int64), offsets


def _interpolation(rows_c, cols_c, rows_f, cols_f):
    """For every particle of the finer level (row by row): the four local nodes of this
    level it interpolates from, their bilinear weights, and the fine box they span."""
    kr, tr = _bracket(rows_c, rows_f)
    kc, tc = _bracket(cols_c, cols_f)
    R, C = np.meshgrid(np.arange(len(rows_f)), np.arange(len(cols_f)), indexing="ij")
    R, C = R.ravel(), C.ravel()
    r0, c0, a, b = kr[R], kc[C], tr[R], tc[C]
    nc = len(cols_c)
    sources = np.stack([r0 * nc + c0, r0 * nc + c0 + 1, (r0 + 1) * nc + c0,
                        (r0 + 1) * nc + c0 + 1], axis=1)
    weights = np.stack([(1 - a) * (1 - b), (1 - a) * b, a * (1 - b), a * b], axis=1)
    box = np.stack([rows_c[r0], rows_c[r0 + 1], cols_c[c0], cols_c[c0 + 1]], axis=1)
    return sources.astype(np.int64), weights, box.astype(np.int64)


def _weigh_up(values: np.ndarray, sources: np.ndarray, weights: np.ndarray,
              count: int) -> np.ndarray:
    """Σ over the finer particles of weight × value, onto each node."""
    out = np.zeros((count,) + values.shape[1:])
    for s in range(4):
        w = weights[:, s].reshape((-1,) + (1,) * (values.ndim - 1))
        np.add.at(out, sources[:, s], w * values)
    return out


def build_levels(model: ClothModel, max_levels: int = 16) -> list[Level]:
    """The model's coarse levels, coarsest first; none for a sheet too small to coarsen or
    with neither structural nor shear constraints (nothing a coarse level could stand for)."""
    fam = model.family
    structural = bool(np.any(fam == STRUCTURAL))
    shear = bool(np.any(fam == SHEAR))
    if not (structural or shear):
        return []
    nx, nz = model.nx, model.nz
    levels = []
    rows_f, cols_f = np.arange(nz), np.arange(nx)
    rest_f, mass_f, inv_f = model.rest_positions, model.mass, model.inv_mass
    for lvl in range(1, max_levels + 1):
        rows_c, cols_c = axis_nodes(nz, 1 << lvl), axis_nodes(nx, 1 << lvl)
        if len(rows_c) < MIN_NODES or len(cols_c) < MIN_NODES or (
                len(rows_c) == len(rows_f) and len(cols_c) == len(cols_f)):
            break
        count = len(rows_c) * len(cols_c)
        sources, weights, tbox = _interpolation(rows_c, cols_c, rows_f, cols_f)
        norm = _weigh_up(np.ones(len(sources)), sources, weights, count)
        mass = _weigh_up(np.asarray(mass_f, np.float64), sources, weights, count)
        nodes = (rows_c[:, None] * nx + cols_c[None, :]).ravel().astype(np.int64)
        own = (np.searchsorted(rows_f, rows_c)[:, None] * len(cols_f)
               + np.searchsorted(cols_f, cols_c)[None, :]).ravel().astype(np.int64)
        inv_c = np.where(model.inv_mass[nodes] > 0.0, 1.0 / mass, 0.0)
        rest_c = _weigh_up(rest_f, sources, weights, count) / norm[:, None]
        rest_c[inv_c == 0.0] = rest_f[own[inv_c == 0.0]]  # a pinned node stands where its pin is
        edges, offsets = _level_edges(len(rows_c), len(cols_c), structural, shear)
        rest = np.linalg.norm(rest_c[edges[:, 1]] - rest_c[edges[:, 0]], axis=1)
        ra, ca = np.divmod(nodes[edges[:, 0]], nx)
        rb, cb = np.divmod(nodes[edges[:, 1]], nx)
        ebox = np.stack([np.minimum(ra, rb), np.maximum(ra, rb), np.minimum(ca, cb),
                         np.maximum(ca, cb)], axis=1).astype(np.int64)
        levels.append(Level(nz=len(rows_c), nx=len(cols_c), nodes=nodes, inv_mass=inv_c,
                            edges=edges, color_offsets=offsets,
                            rest=rest, edge_box=ebox, sources=sources, weights=weights,
                            own=own, free=(np.asarray(inv_f) > 0.0).astype(np.uint8),
                            target_box=tbox))
        rows_f, cols_f, rest_f, mass_f, inv_f = rows_c, cols_c, rest_c, mass, inv_c
    return levels[::-1]


def torn_flags(model: ClothModel, alive: np.ndarray, boxes: np.ndarray) -> np.ndarray:
    """uint8 per box (rows lo, hi, columns lo, hi of fine particles, inclusive): 1 where no
    particle inside it ends a torn constraint, else 0."""
    dead = model.edges[alive == 0]
    if not len(dead):
        return np.ones(len(boxes), np.uint8)
    mask = np.zeros(model.nz * model.nx, np.int64)
    mask[dead.ravel()] = 1
    s = np.zeros((model.nz + 1, model.nx + 1), np.int64)
    s[1:, 1:] = mask.reshape(model.nz, model.nx).cumsum(0).cumsum(1)
    r0, r1, c0, c1 = boxes.T
    count = s[r1 + 1, c1 + 1] - s[r0, c1 + 1] - s[r1 + 1, c0] + s[r0, c0]
    return (count == 0).astype(np.uint8)
