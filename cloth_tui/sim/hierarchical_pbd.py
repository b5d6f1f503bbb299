"""Hierarchical PBD: each substep, the coarse levels (hierarchy.py) are projected coarsest
first, each level's correction handed down by interpolation, before the fine Gauss-Seidel
passes (xpbd.py's sweeps, α = 0).

Why: a Gauss-Seidel pass carries a correction about one particle, so the stretch a load
leaves on a taut n × n sheet falls only after ~n² passes, and the substeps that keep it under
a tolerance grow with n. A level of spacing 2^l carries it 2^l particles a pass at a quarter
of the work of the level below, so the low-frequency part of the error is gone before the
fine passes start, which then only smooth what lies between coarse particles.

The cascade, per substep: restrict the sheet's positions up through the levels (each node
the weighted mean of the finer particles around it, hierarchy.py); then from the coarsest
level down, start each level at its restriction plus the interpolated displacement of the
level above, run one-sided Gauss-Seidel passes over its constraints (more on coarser levels,
which are cheap), and keep its displacement from its restriction; the sheet's particles get
the finest level's displacement, interpolated. Contacts, friction, pins and tearing act on
the fine sheet as with plain PBD (pipeline.assemble's stages around the projection).
"""

from __future__ import annotations

import math

import numpy as np

from .hierarchy import Level, build_levels, torn_flags
from .jit import kernel

COARSE_PASSES = 2  # one-sided passes per substep on the finest coarse level
MAX_LEVEL_PASSES = 64  # (a 3 × 3 level is solved long before)


@kernel(inline="always")
def _project_level(p, w, edges, rest, alive, lo, hi):
    """One pass over edges [lo, hi) of a level: pull a pair together where it is farther
    apart than its rest length (one-sided: a closer pair is left alone)."""
    for e in range(lo, hi):
        if not alive[e]:
            continue
        a = edges[e, 0]
        b = edges[e, 1]
        wa = w[a]
        wb = w[b]
        if wa + wb == 0.0:
            continue
        dx = p[b, 0] - p[a, 0]
        dy = p[b, 1] - p[a, 1]
        dz = p[b, 2] - p[a, 2]
        d = math.sqrt(dx * dx + dy * dy + dz * dz)
        if not d > rest[e]:  # (a NaN fails too and stays in the positions for the guard)
            continue
        s = (rest[e] - d) / (d * (wa + wb))
        p[a, 0] -= wa * s * dx
        p[a, 1] -= wa * s * dy
        p[a, 2] -= wa * s * dz
        p[b, 0] += wb * s * dx
        p[b, 1] += wb * s * dy
        p[b, 2] += wb * s * dz


@kernel(inline="always")
def _restrict(src, dst, sources, weights, total, w, own, cell_alive):
    """dst ← full weighting of src (the finer level's positions) by the level's weights,
    leaving out finer particles whose cell a tear touches (their nodes may stand for both
    sides of it); a pinned node (w 0), or one with nothing left to weigh, takes its own
    particle's position. `total` is scratch for the weights' sums."""
    for k in range(dst.shape[0]):
        dst[k, 0] = 0.0
        dst[k, 1] = 0.0
        dst[k, 2] = 0.0
        total[k] = 0.0
    for t in range(src.shape[0]):
        if not cell_alive[t]:
            continue
        for s in range(4):
            k = sources[t, s]
            wt = weights[t, s]
            dst[k, 0] += wt * src[t, 0]
            dst[k, 1] += wt * src[t, 1]
            dst[k, 2] += wt * src[t, 2]
            total[k] += wt
    for k in range(dst.shape[0]):
        if w[k] == 0.0 or total[k] == 0.0:
            dst[k, 0] = src[own[k], 0]
            dst[k, 1] = src[own[k], 1]
            dst[k, 2] = src[own[k], 2]
        else:
            inv = 1.0 / total[k]
            dst[k, 0] *= inv
            dst[k, 1] *= inv
            dst[k, 2] *= inv


@kernel(inline="always")
def _prolong(delta, dst, sources, weights, free, cell_alive):
    """dst += the bilinear interpolation of a level's displacements, where dst may move."""
    for t in range(dst.shape[0]):
        if not (free[t] and cell_alive[t]):
            continue
        for c in range(3):
            acc = 0.0
            for s in range(4):
                acc += weights[t, s] * delta[sources[t, s], c]
            dst[t, c] += acc


@kernel(_nrt=False)
def cascade(x, r, p, total, node_off, w, own, edge_off, edges, rest, alive, fine_off, sources,
            weights, free, cell_alive, passes):
    """The cascade of the module docstring over levels concatenated coarsest first: level
    k's nodes are [node_off[k], node_off[k+1]) of `w`, `own`, `r` and `p`, its edges
    [edge_off[k], edge_off[k+1]) (local node pairs), and its weights for the finer level's
    particles (the sheet's, below the last level) [fine_off[k], fine_off[k+1]).
    `r`, `p` and `total` are scratch: each level's restricted and projected positions, and
    the sums of the weights restricted."""
    levels = node_off.shape[0] - 1
    for k in range(levels - 1, -1, -1):  # restrict, finest first
        f0, f1 = fine_off[k], fine_off[k + 1]
        n0, n1 = node_off[k], node_off[k + 1]
        finer = x if k == levels - 1 else r[node_off[k + 1]:node_off[k + 2]]
        _restrict(finer, r[n0:n1], sources[f0:f1], weights[f0:f1], total[n0:n1], w[n0:n1],
                  own[n0:n1], cell_alive[f0:f1])
    for k in range(levels):  # project, coarsest first
        n0, n1 = node_off[k], node_off[k + 1]
        pk = p[n0:n1]
        for i in range(n1 - n0):
            pk[i, 0] = r[n0 + i, 0]
            pk[i, 1] = r[n0 + i, 1]
            pk[i, 2] = r[n0 + i, 2]
        if k > 0:  # the coarser level's displacements, in p[coarser]
            c0, c1, f0, f1 = node_off[k - 1], node_off[k], fine_off[k - 1], fine_off[k]
            _prolong(p[c0:c1], pk, sources[f0:f1], weights[f0:f1], free[f0:f1],
                     cell_alive[f0:f1])
        e0, e1 = edge_off[k], edge_off[k + 1]
        for _ in range(passes[k]):
            _project_level(pk, w[n0:n1], edges[e0:e1], rest[e0:e1], alive[e0:e1], 0, e1 - e0)
        for i in range(n1 - n0):  # p now holds the level's displacement from its restriction
            pk[i, 0] -= r[n0 + i, 0]
            pk[i, 1] -= r[n0 + i, 1]
            pk[i, 2] -= r[n0 + i, 2]
    k = levels - 1
    f0, f1 = fine_off[k], fine_off[k + 1]
    _prolong(p[node_off[k]:node_off[k + 1]], x, sources[f0:f1], weights[f0:f1], free[f0:f1],
             cell_alive[f0:f1])


class ProjectHierarchy:
    """The coarse levels' cascade, a stage before the fine projection: `passes` one-sided
    passes per substep on the finest coarse level, more on coarser ones (level_passes)."""

    name = "project_coarse_levels"

    def __init__(self, model, passes: int = COARSE_PASSES):
        self.model = model
        self.passes = passes
        self._build()

    def _build(self) -> None:
        """The levels of the model as it is now, and the kernel's arrays of them."""
        model, passes = self.model, self.passes
        self.levels: list[Level] = build_levels(model)
        lv = self.levels

        def cat(arrs, shape, dtype=np.float64):
            return np.ascontiguousarray(np.concatenate(arrs) if arrs else np.zeros(shape),
                                        dtype=dtype)

        self._node_off = _offsets([len(v.nodes) for v in lv])
        self._edge_off = _offsets([len(v.edges) for v in lv])
        self._fine_off = _offsets([len(v.sources) for v in lv])
        self._w = cat([v.inv_mass for v in lv], 0)
        self._own = cat([v.own for v in lv], 0, np.int64)
        self._edges = cat([v.edges for v in lv], (0, 2), np.int64)
        self._rest = cat([v.rest for v in lv], 0)
        self._sources = cat([v.sources for v in lv], (0, 4), np.int64)
        self._weights = cat([v.weights for v in lv], (0, 4))
        self._free = cat([v.free for v in lv], 0, np.uint8)
        self._edge_box = cat([v.edge_box for v in lv], (0, 4), np.int64)
        self._cell_box = cat([v.target_box for v in lv], (0, 4), np.int64)
        self._alive = np.ones(len(self._edges), np.uint8)
        self._cell_alive = np.ones(len(self._sources), np.uint8)
        self._seen_alive: np.ndarray | None = None  # the fine `alive` the flags were made for
        self._r = np.zeros((int(self._node_off[-1]), 3))
        self._p = np.zeros_like(self._r)
        self._total = np.zeros(len(self._r))
        self._passes = level_passes(len(lv), passes)

    def refresh_masses(self) -> None:
        """The levels again from the model's masses (written in place: model.refitted)."""
        self._build()

    @property
    def projections(self) -> int:
        """Coarse constraint projections per substep (the bench counts the cascade's work in
        fine passes by it)."""
        return int(sum(int(p) * len(v.edges) for p, v in zip(self._passes, self.levels)))

    def apply(self, state, h):
        if not self.levels:
            return
        self._follow_tears(state.alive, state.torn)
        cascade(state.x, self._r, self._p, self._total, self._node_off, self._w, self._own,
                self._edge_off, self._edges, self._rest, self._alive, self._fine_off,
                self._sources, self._weights, self._free, self._cell_alive, self._passes)

    def _follow_tears(self, alive: np.ndarray, torn: int) -> None:
        """Leave out the coarse constraints and interpolation cells a tear touches (made
        again only when the fine sheet's `alive` changed: a tear, a cut, an undone frame)."""
        seen = self._seen_alive
        if seen is None and not torn:
            return
        if seen is not None and np.array_equal(seen, alive):
            return
        if not torn:
            self._alive[:] = 1
            self._cell_alive[:] = 1
            self._seen_alive = None
            return
        self._alive = torn_flags(self.model, alive, self._edge_box)
        self._cell_alive = torn_flags(self.model, alive, self._cell_box)
        self._seen_alive = alive.copy()


def level_passes(levels: int, passes: int) -> np.ndarray:
    """Passes per level, coarsest first: `passes` on the finest coarse level, twice as many
    on each coarser one. A level of spacing 2^l costs 4^−l of the sheet a pass, so together
    they cost at most the passes of the finest coarse level again; the coarse error the
    fine passes cannot reach falls with them (measured at 128²: a frame's error 0.043 with 2
    passes on every level, 0.028 doubling)."""
    return np.array([min(passes << (levels - 1 - k), MAX_LEVEL_PASSES) for k in range(levels)],
                    np.int64)


def _offsets(counts: list[int]) -> np.ndarray:
    return np.concatenate([[0], np.cumsum(counts)]).astype(np.int64) if counts \
        else np.zeros(1, np.int64)
