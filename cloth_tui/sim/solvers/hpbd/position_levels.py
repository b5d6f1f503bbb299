"""Hierarchical PBD: each substep, the coarse levels (level_grids.py) are projected coarsest
first, each level's correction handed down by interpolation, before the fine Gauss-Seidel
passes (xpbd/constraints.py's sweeps, α = 0).

Why: a Gauss-Seidel pass carries a correction about one particle, so the stretch a load
leaves on a taut n × n sheet falls only after ~n² passes, and the substeps that keep it under
a tolerance grow with n. A level of spacing 2^l carries it 2^l particles a pass at a quarter
of the work of the level below, so the low-frequency part of the error is gone before the
fine passes start, which then only smooth what lies between coarse particles.

The cascade, per substep: restrict the sheet's positions up through the levels (each node
the weighted mean of the finer particles around it, level_grids.py); then from the coarsest
level down, start each level at its restriction plus the interpolated displacement of the
level above, run one-sided Gauss-Seidel passes over its constraints (more on coarser levels,
which are cheap), and keep its displacement from its restriction; the sheet's particles get
the finest level's displacement, interpolated. Contacts, friction, pins and tearing act on
the fine sheet as with plain PBD (pipeline.assemble's stages around the projection).

Each level is an nz × nx grid whose constraints take grid_sweeps' first 8 colours, so a
level of 1,024 nodes or more runs its passes as that module's vector runs (`project_level`);
`cascade_loop`, plain loops over each level's constraint list, is the reference a test holds
them to.
"""

from __future__ import annotations

import math

import numpy as np

from ...grid_sweeps import NUM_COLORS, SweepPlan, SweepScratch, correct_pair, plan_sweeps
from .level_grids import Level, build_levels, torn_flags
from ...jit import kernel

COARSE_PASSES = 2  # one-sided passes per substep on the finest coarse level
MAX_LEVEL_PASSES = 64  # (a 3 × 3 level is solved long before)
# Levels with fewer nodes run their passes as a loop over their constraint list, not as
# grid_sweeps' runs, whose set-up a small level does not repay (measured: docs/physics.md)
SWEEP_MIN_NODES = 1024


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
def cascade_loop(x, r, p, total, node_off, w, own, edge_off, edges, rest, alive, fine_off,
                 sources, weights, free, cell_alive, passes):
    """The cascade of the module docstring as plain loops over each level's constraint list,
    one thread: the reference ProjectHierarchy's sweeps are tested against. Levels are
    concatenated coarsest first: level
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


@kernel(_nrt=False)
def restrict_levels(x, r, total, node_off, w, own, fine_off, sources, weights, cell_alive):
    """Every level's restriction of the sheet's positions x into `r`, finest level first
    (the arrays as cascade_loop's)."""
    levels = node_off.shape[0] - 1
    for k in range(levels - 1, -1, -1):
        f0, f1 = fine_off[k], fine_off[k + 1]
        n0, n1 = node_off[k], node_off[k + 1]
        finer = x if k == levels - 1 else r[node_off[k + 1]:node_off[k + 2]]
        _restrict(finer, r[n0:n1], sources[f0:f1], weights[f0:f1], total[n0:n1], w[n0:n1],
                  own[n0:n1], cell_alive[f0:f1])


# As grid_sweeps' runs: its own (not inlined) function of slices, so LLVM bounds them and
# vectorises the loop; the one-sided test is a select, not a branch.
@kernel()
def _run_one_sided(xa, ya, za, xb, yb, zb, wa_run, wb_run, rest, alive):
    """`_project_level`'s update for every pair of a run of a level's sweep layout."""
    for t in range(xa.shape[0]):
        wa = wa_run[t]
        wb = wb_run[t]
        dx = xb[t] - xa[t]
        dy = yb[t] - ya[t]
        dz = zb[t] - za[t]
        d = math.sqrt(dx * dx + dy * dy + dz * dz)
        # a closer pair, a coincident one (d 0) and a NaN all fail `d > rest` and stay
        s = (rest[t] - d) / (d * (wa + wb)) if d > rest[t] and wa + wb > 0.0 else 0.0
        correct_pair(xa, ya, za, wa, xb, yb, zb, wb, t, s * alive[t], dx, dy, dz)


@kernel(_nrt=False)
def project_level(r, coarser, p, sources, weights, free, cell_alive, w, edges, rest, alive,
                  P, W, grid_offset, chunks, color_chunks, edge_slot, slot_rest, alive_seen,
                  slot_alive, passes, sweeps):
    """One level of the cascade: start at its restriction `r` plus the interpolation of the
    coarser level's displacement `coarser` (by `sources`, `weights`: none for the coarsest),
    run `passes` one-sided passes, and leave the level's displacement from `r` in `p`.
    With `sweeps`, the passes run in grid_sweeps' layout (the level's plan: P, W,
    grid_offset, chunks, colours and slots; `alive`, the level's flags in its own order, is
    taken into slot order where it changed); without, as cascade_loop's loop over `edges`
    (a level too small for runs to pay: a 5 × 5 level's 64 passes are thousands of runs a
    few pairs long)."""
    for i in range(r.shape[0]):
        p[i, 0], p[i, 1], p[i, 2] = r[i, 0], r[i, 1], r[i, 2]
    if sources.shape[0]:
        _prolong(coarser, p, sources, weights, free, cell_alive)
    if sweeps:
        for i in range(r.shape[0]):
            g = grid_offset[i]
            P[0, g], P[1, g], P[2, g] = p[i, 0], p[i, 1], p[i, 2]
        for e in range(alive.shape[0]):
            if alive[e] != alive_seen[e]:
                alive_seen[e] = alive[e]
                slot_alive[edge_slot[e]] = alive[e]
        for _ in range(passes):
            for c in range(NUM_COLORS):
                for q in range(color_chunks[c], color_chunks[c + 1]):
                    a0, b0, s0, n = chunks[q, 0], chunks[q, 1], chunks[q, 2], chunks[q, 3]
                    _run_one_sided(P[0, a0:a0 + n], P[1, a0:a0 + n], P[2, a0:a0 + n],
                                   P[0, b0:b0 + n], P[1, b0:b0 + n], P[2, b0:b0 + n],
                                   W[a0:a0 + n], W[b0:b0 + n], slot_rest[s0:s0 + n],
                                   slot_alive[s0:s0 + n])
        for i in range(r.shape[0]):
            g = grid_offset[i]
            p[i, 0], p[i, 1], p[i, 2] = P[0, g], P[1, g], P[2, g]
    else:
        for _ in range(passes):
            _project_level(p, w, edges, rest, alive, 0, edges.shape[0])
    for i in range(r.shape[0]):
        p[i, 0] -= r[i, 0]
        p[i, 1] -= r[i, 1]
        p[i, 2] -= r[i, 2]


@kernel(_nrt=False)
def prolong_to_sheet(delta, x, sources, weights, free, cell_alive):
    """The sheet's particles get the finest level's displacement `delta`, interpolated."""
    _prolong(delta, x, sources, weights, free, cell_alive)


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
        self._seen_inv_mass = model.inv_mass.copy()  # the masses the levels weigh
        # each level's constraints as grid_sweeps' colour runs over its own nz × nx grid
        self._plans: list[tuple[SweepPlan, SweepScratch]] = []
        for v in lv:
            plan = plan_sweeps(v.nx, v.nz, v.edges, v.color_offsets, v.rest, v.inv_mass)
            self._plans.append((plan, plan.scratch()))

    def refresh_masses(self) -> None:
        """The levels' masses again from the model's (written in place: model.refitted),
        where they changed: the solver asks on every change of its params, and rebuilding
        the levels and their sweep plans would hold a slider's every move. Which nodes are
        pinned does not change here, so only the inverse masses are written."""
        if np.array_equal(self._seen_inv_mass, self.model.inv_mass):
            return
        levels = build_levels(self.model)
        self._w[:] = np.concatenate([v.inv_mass for v in levels])
        for v, (plan, _) in zip(levels, self._plans):
            plan.inv_mass[plan.grid_offset] = v.inv_mass
        self.levels = levels
        self._seen_inv_mass = self.model.inv_mass.copy()

    @property
    def projections(self) -> int:
        """Coarse constraint projections per substep (the bench counts the cascade's work in
        fine passes by it)."""
        return int(sum(int(p) * len(v.edges) for p, v in zip(self._passes, self.levels)))

    def apply(self, state, h):
        if not self.levels:
            return
        self._follow_tears(state.alive, state.torn)
        no, eo, fo = self._node_off, self._edge_off, self._fine_off
        restrict_levels(state.x, self._r, self._total, no, self._w, self._own, fo,
                        self._sources, self._weights, self._cell_alive)
        for k, (plan, scratch) in enumerate(self._plans):
            # the weights that carry level k − 1's displacement down to level k (none for
            # the coarsest) are level k − 1's
            c0, c1 = (no[k - 1], no[k]) if k else (0, 0)
            f0, f1 = (fo[k - 1], fo[k]) if k else (0, 0)
            n0, n1, e0, e1 = no[k], no[k + 1], eo[k], eo[k + 1]
            project_level(self._r[n0:n1], self._p[c0:c1], self._p[n0:n1],
                          self._sources[f0:f1], self._weights[f0:f1], self._free[f0:f1],
                          self._cell_alive[f0:f1], self._w[n0:n1], self._edges[e0:e1],
                          self._rest[e0:e1], self._alive[e0:e1], plan.positions,
                          plan.inv_mass, plan.grid_offset, plan.chunks, plan.color_chunks,
                          plan.edge_slot, plan.rest, scratch.alive_seen, scratch.slot_alive,
                          self._passes[k], n1 - n0 >= SWEEP_MIN_NODES)
        k = len(self._plans) - 1
        prolong_to_sheet(self._p[no[k]:no[k + 1]], state.x, self._sources[fo[k]:fo[k + 1]],
                         self._weights[fo[k]:fo[k + 1]], self._free[fo[k]:fo[k + 1]],
                         self._cell_alive[fo[k]:fo[k + 1]])

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
