"""Colour sweeps over the regular grid: xpbd/constraints.py's projection as long vector loops.

Every constraint of the sheet joins grid particle (i, j) to (i + di, j + dj) for one of six
offsets, and grid.py's 12 colours split each offset by the parity of a row or a column (or
of its half, for bending). The sheet has nz rows of nx particles. The sweeps keep positions
in a structure-of-arrays scratch grid of 16 blocks, one per (i mod 4, j mod 4), each h rows
of w places with h = ⌈nz/4⌉ and w = ⌈nx/4⌉: particle (i, j) sits at k·w + m of its block,
k = i div 4, m = j div 4. Since 4 is a multiple of every colour's period, a colour takes
whole blocks, and all pairs whose first particle lies in block A have their second in one
block B at one fixed offset: a colour is at most 16 runs a[t] – b[t + Δ], each up to h·w
long, that vectorise (one run per row and lane would make the runs short, and setting each
up would cost as much as sweeping it).

A run that steps across a column edge (m + 1 = w) pairs particles that are not neighbours,
and a run's ends may pair a particle with grid padding. Those pairs keep a slot whose
`alive` is 0, so the branch-free update moves nothing there; no such pair touches a
particle that a real constraint of its colour moves (colours are conflict-free, and a
wrapped pair's ends are in the first or last column, where its colour has no constraint),
so even threads sharing a colour do not race. Each slot's rest length, `alive` flag and
multiplier λ are kept in sweep order (`SweepPlan.slot_edge` maps slots to model.edges).
Runs are cut into chunks of at most CHUNK pairs: the unit a thread takes.
"""

from __future__ import annotations

import math
from dataclasses import dataclass

import numpy as np
from numba import prange

from .grid import NUM_COLORS, OFFSETS, color_of, grid_colors
from .jit import kernel

COINCIDENT = 1e-12  # m: ends closer than this have no direction of their own
BLOCKS = 4  # rows and columns are split by index mod 4
CHUNK = 512  # pairs a thread takes at a time (a multiple of the vector width)
# Doubles between blocks and planes, so that a and b (and x, y, z) of one pair do not lie a
# multiple of 4 KiB apart, where loads wait on unrelated stores (4K aliasing)
BLOCK_PAD = 8
PLANE_SKEW = 1088  # bytes: y's plane starts this far past x's modulo 4 KiB, z's twice as far


UNSEEN = 2  # alive_seen's value before the first sweep: differs from both 0 and 1


@dataclass(frozen=True)
class SweepScratch:
    """What one solver's sweeps keep between calls, in slot order."""

    slot_alive: np.ndarray  # (S,) float 1.0 or 0.0: `alive` per slot, 0 where no constraint
    alive_seen: np.ndarray  # (M,) uint8: `alive` as slot_alive last took it (model order)
    lam: np.ndarray         # (S,) λ of the current substep (XPBD)


@dataclass(frozen=True)
class SweepPlan:
    """Where the sweeps keep things for one model (NumPy, built once; see the module)."""

    nx: int                  # particles in a row of the sheet
    width: int               # w = ⌈nx/4⌉: places in a row of a block
    block: int               # doubles per block, h·w + BLOCK_PAD, h = ⌈nz/4⌉
    grid_offset: np.ndarray  # (nx·nz,) int64: particle p's place in a plane
    inv_mass: np.ndarray     # (plane,) inverse masses in the layout (padding 0)
    chunks: np.ndarray       # (K, 4) int64: a's first place, b's first place, first slot, length
    color_chunks: np.ndarray  # (13,) int64: colour c's chunks are [cc[c], cc[c+1])
    slot_edge: np.ndarray    # (S,) int64: the constraint in model.edges, −1 for none
    edge_slot: np.ndarray    # (M,) int64: each constraint's slot
    rest: np.ndarray         # (S,) rest length of each slot (0 where none)
    positions: np.ndarray    # (3, plane) scratch positions

    @property
    def slots(self) -> int:
        return len(self.slot_edge)

    def scratch(self) -> SweepScratch:
        """Fresh per-solver scratch for `sweep`."""
        return SweepScratch(slot_alive=np.zeros(self.slots),
                            alive_seen=np.full(len(self.edge_slot), UNSEEN, np.uint8),
                            lam=np.zeros(self.slots))


def plan_sweeps(nx: int, nz: int, edges: np.ndarray, color_offsets: np.ndarray,
                rest: np.ndarray, inv_mass: np.ndarray) -> SweepPlan:
    """The sweeps' layout and runs for a grid model of nz rows of nx particles. ValueError
    unless every constraint joins grid neighbours and the model's colours are the sweeps' (in
    the same order)."""
    w, h = -(-nx // BLOCKS), -(-nz // BLOCKS)
    block = h * w + BLOCK_PAD
    plane = BLOCKS * BLOCKS * block
    plane += ((PLANE_SKEW - plane * 8) % 4096) // 8
    i, j = np.divmod(np.arange(nx * nz), nx)
    grid_offset = ((i % BLOCKS) * BLOCKS + j % BLOCKS) * block + (i // BLOCKS) * w + j // BLOCKS
    w_grid = np.zeros(plane)
    w_grid[grid_offset] = inv_mass

    colors = grid_colors(edges, nx)
    for lo, hi in zip(color_offsets[:-1], color_offsets[1:]):
        if len(set(colors[lo:hi].tolist())) != 1:
            raise ValueError("the model's colours are not the grid sweeps' colours")
    present = [int(colors[lo]) for lo in color_offsets[:-1]]
    if present != sorted(set(present)):
        raise ValueError("the model's colours are not in the grid sweeps' order")

    chunks, color_chunks, slot_a, slot_b = [], [0], [], []
    for c in range(NUM_COLORS):
        for a_first, b_first, pair_a, pair_b in (_runs(c, nx, nz, block) if c in present
                                                 else ()):
            first_slot = sum(len(a) for a in slot_a)
            for t in range(0, len(pair_a), CHUNK):
                chunks.append((a_first + t, b_first + t, first_slot + t,
                               min(CHUNK, len(pair_a) - t)))
            slot_a.append(pair_a)
            slot_b.append(pair_b)
        color_chunks.append(len(chunks))

    slot_a = np.concatenate(slot_a) if slot_a else np.zeros(0, np.int64)
    slot_b = np.concatenate(slot_b) if slot_b else np.zeros(0, np.int64)
    slot_edge = _match_slots(slot_a, slot_b, edges, nx * nz)
    slot_rest = np.zeros(len(slot_edge))
    slot_rest[slot_edge >= 0] = rest[slot_edge[slot_edge >= 0]]
    edge_slot = np.zeros(len(edges), np.int64)
    edge_slot[slot_edge[slot_edge >= 0]] = np.flatnonzero(slot_edge >= 0)
    return SweepPlan(nx=nx, width=w, block=block, grid_offset=grid_offset, inv_mass=w_grid,
                     chunks=np.array(chunks, np.int64).reshape(-1, 4),
                     color_chunks=np.array(color_chunks, np.int64), slot_edge=slot_edge,
                     edge_slot=edge_slot,
                     rest=slot_rest, positions=np.zeros((3, plane)))


def _runs(c: int, nx: int, nz: int, block: int):
    """Colour c's runs, one per block its pairs start in: the places of the first a and b,
    and the particles each pair of the run joins (−1, −1 where it joins no grid neighbours:
    padding or a wrap across a column edge)."""
    di, dj = OFFSETS[c]
    w, h = -(-nx // BLOCKS), -(-nz // BLOCKS)
    places = h * w
    for ra in range(BLOCKS):
        for qa in range(BLOCKS):
            if not color_of(c, ra, qa):
                continue
            dk, rb = divmod(ra + di, BLOCKS)
            dm, qb = divmod(qa + dj, BLOCKS)
            shift = dk * w + dm  # b's place − a's place inside their blocks
            t = np.arange(max(0, -shift), max(0, min(places, places - shift)))
            k, m = np.divmod(t, w)
            ia, ja = BLOCKS * k + ra, BLOCKS * m + qa
            kb, mb = np.divmod(t + shift, w)
            ib, jb = BLOCKS * kb + rb, BLOCKS * mb + qb
            real = (ia < nz) & (ja < nx) & (ib == ia + di) & (jb == ja + dj) & (ib < nz) \
                & (jb >= 0) & (jb < nx)
            if len(t):
                yield ((ra * BLOCKS + qa) * block + t[0], (rb * BLOCKS + qb) * block + shift
                       + t[0], np.where(real, ia * nx + ja, -1),
                       np.where(real, ib * nx + jb, -1))


def _match_slots(slot_a: np.ndarray, slot_b: np.ndarray, edges: np.ndarray,
                 particles: int) -> np.ndarray:
    """The constraint of each slot (−1: none); ValueError unless each constraint has one."""
    slot_edge = np.full(len(slot_a), -1, np.int64)
    if len(edges):
        key = edges[:, 0] * particles + edges[:, 1]
        order = np.argsort(key)
        sorted_key = key[order]
        slot_key = slot_a * particles + slot_b
        at = np.minimum(np.searchsorted(sorted_key, slot_key), len(key) - 1)
        found = (slot_a >= 0) & (sorted_key[at] == slot_key)
        slot_edge[found] = order[at[found]]
    if np.count_nonzero(slot_edge >= 0) != len(edges):
        raise ValueError("some constraints do not join grid neighbours of their colour")
    return slot_edge


@kernel(inline="always")
def coincident_direction(a, b):
    """The separation (length COINCIDENT) given to constraint a–b when its ends coincide and have no
    direction of their own: any fixed, pair-dependent direction will do, so a crushed sheet unfolds
    instead of staying collapsed. One rule for the plain loop (xpbd/constraints.py) and the sweeps,
    so both unfold a sheet the same way."""
    dx = math.sin(1.3 * a + 7.1 * b)
    dy = math.cos(3.7 * a - 1.9 * b)
    dz = math.sin(2.3 * a + 0.7 * b + 1.0)
    scale = COINCIDENT / math.sqrt(dx * dx + dy * dy + dz * dz)
    return dx * scale, dy * scale, dz * scale


@kernel(inline="always")
def correct_pair(xa, ya, za, wa, xb, yb, zb, wb, t, s, dx, dy, dz):
    """Pair t's correction: its ends move apart along (dx, dy, dz) by s, weighted by their
    inverse masses wa, wb."""
    xa[t] -= wa * s * dx
    ya[t] -= wa * s * dy
    za[t] -= wa * s * dz
    xb[t] += wb * s * dx
    yb[t] += wb * s * dy
    zb[t] += wb * s * dz


# A run's pair loop is its own (not inlined) function of its arrays, each a slice of the
# layout: then LLVM can bound them and check at run time that they do not overlap (they
# never do: a and b lie in different blocks), and vectorises the loop. Inlined into the
# chunk, the slices' bounds were lost ("cannot identify array bounds") and the loop stayed
# scalar. `alive` enters as a factor, not a branch: with `not alive[t]` in the select,
# LLVM's cost model found the vector loop not worth it (docs/benchmarks.md has the rates).


@kernel()
def _run_rigid(xa, ya, za, xb, yb, zb, wa_run, wb_run, rest, alive):
    """PBD's projection (α = 0, no λ kept) of every pair of a run; returns how many live
    pairs have coincident ends (left to `_crushed_pair`)."""
    crushed_live = 0.0
    for t in range(xa.shape[0]):
        wa = wa_run[t]
        wb = wb_run[t]
        dx = xb[t] - xa[t]
        dy = yb[t] - ya[t]
        dz = zb[t] - za[t]
        d2 = dx * dx + dy * dy + dz * dz
        crushed = d2 < COINCIDENT * COINCIDENT
        d = math.sqrt(1.0 if crushed else d2)
        s = (rest[t] - d) / (d * (wa + wb)) if wa + wb > 0.0 else 0.0
        s = 0.0 if crushed else s * alive[t]
        correct_pair(xa, ya, za, wa, xb, yb, zb, wb, t, s, dx, dy, dz)
        crushed_live += alive[t] if crushed else 0.0
    return crushed_live


@kernel()
def _run_compliant(xa, ya, za, xb, yb, zb, wa_run, wb_run, rest, alive, lam, alpha_t,
                   alpha_run, per_slot):
    """XPBD's projection of every pair of a run, λ kept in `lam`: α̃ is `alpha_t` for
    every pair, or each pair's own `alpha_run[t]` when `per_slot` (a material's). Returns
    as `_run_rigid`."""
    crushed_live = 0.0
    for t in range(xa.shape[0]):
        a_t = alpha_run[t] if per_slot else alpha_t
        wa = wa_run[t]
        wb = wb_run[t]
        dx = xb[t] - xa[t]
        dy = yb[t] - ya[t]
        dz = zb[t] - za[t]
        d2 = dx * dx + dy * dy + dz * dz
        crushed = d2 < COINCIDENT * COINCIDENT
        d = math.sqrt(1.0 if crushed else d2)
        lam_t = lam[t]
        s = (rest[t] - d - a_t * lam_t) / (d * (wa + wb + a_t)) if wa + wb > 0.0 else 0.0
        s = 0.0 if crushed else s * alive[t]
        correct_pair(xa, ya, za, wa, xb, yb, zb, wb, t, s, dx, dy, dz)
        lam[t] = lam_t + s * d
        crushed_live += alive[t] if crushed else 0.0
    return crushed_live


@kernel(inline="always")
def _crushed_pair(xa, ya, za, wa_run, xb, yb, zb, wb_run, t, rest, alive, lam, alpha_t,
                  keeps_lambda, a, b):
    """The pairs `_pair` left: ends (particles a and b) closer than COINCIDENT separate along
    xpbd/constraints.py's fixed, pair-dependent direction, so a crushed sheet unfolds exactly as
    with the plain loop. Pairs of one colour share no particle, so doing these after the rest of
    their chunk changes nothing."""
    wa = wa_run[t]
    wb = wb_run[t]
    dx = xb[t] - xa[t]
    dy = yb[t] - ya[t]
    dz = zb[t] - za[t]
    if alive[t] and wa + wb > 0.0 and dx * dx + dy * dy + dz * dz < COINCIDENT * COINCIDENT:
        dx, dy, dz = coincident_direction(a, b)
        d = COINCIDENT
        lam_t = lam[t] if keeps_lambda else 0.0  # PBD's λ is neither reset nor kept
        s = (rest[t] - d - alpha_t * lam_t) / (d * (wa + wb + alpha_t))
        correct_pair(xa, ya, za, wa, xb, yb, zb, wb, t, s, dx, dy, dz)
        if keeps_lambda:
            lam[t] = lam_t + s * d


@kernel(inline="always")
def _particle(place, nx, width, block):
    """The sheet's particle index of a place in the layout (rows of nx particles)."""
    b, rem = place // block, place % block
    k, m = rem // width, rem % width
    return (BLOCKS * k + b // BLOCKS) * nx + BLOCKS * m + b % BLOCKS


@kernel(inline="always")
def _project_chunk(P, W, rest, alive, lam, chunks, q, alpha_t, alpha_slots, nx, width, block):
    """Every pair of chunk q: the vector pass, then the rare coincident pairs. α̃ is
    `alpha_t` for every pair, or, when `alpha_slots` is not empty, each slot's own (a
    material's compliance per edge)."""
    a0, b0, s0, count = chunks[q, 0], chunks[q, 1], chunks[q, 2], chunks[q, 3]
    xa, ya, za = P[0, a0:a0 + count], P[1, a0:a0 + count], P[2, a0:a0 + count]
    xb, yb, zb = P[0, b0:b0 + count], P[1, b0:b0 + count], P[2, b0:b0 + count]
    wa, wb = W[a0:a0 + count], W[b0:b0 + count]
    rest_q, alive_q, lam_q = rest[s0:s0 + count], alive[s0:s0 + count], lam[s0:s0 + count]
    per_slot = alpha_slots.shape[0] > 0
    if per_slot or alpha_t != 0.0:
        alpha_q = alpha_slots[s0:s0 + count] if per_slot else alpha_slots
        left = _run_compliant(xa, ya, za, xb, yb, zb, wa, wb, rest_q, alive_q, lam_q, alpha_t,
                              alpha_q, per_slot)
    else:
        left = _run_rigid(xa, ya, za, xb, yb, zb, wa, wb, rest_q, alive_q)
    if left:
        for t in range(count):
            _crushed_pair(xa, ya, za, wa, xb, yb, zb, wb, t, rest_q, alive_q, lam_q,
                          alpha_slots[s0 + t] if per_slot else alpha_t,
                          per_slot or alpha_t != 0.0, _particle(a0 + t, nx, width, block),
                          _particle(b0 + t, nx, width, block))


@kernel(inline="always")
def _begin(x, alive, P, grid_offset, edge_slot, alive_seen, slot_alive, lam, reset):
    """Positions into the layout; the constraints whose `alive` changed since the last call
    (tearing, a cut, an undo) into slot order (slots with no constraint stay 0): comparing
    in model order reads 2 bytes a constraint where a gather into every slot read 9. XPBD's
    λ reset (`reset`): it accumulates over one substep's passes."""
    for p in range(grid_offset.shape[0]):
        g = grid_offset[p]
        P[0, g] = x[p, 0]
        P[1, g] = x[p, 1]
        P[2, g] = x[p, 2]
    for e in range(alive.shape[0]):
        if alive[e] != alive_seen[e]:
            alive_seen[e] = alive[e]
            slot_alive[edge_slot[e]] = alive[e]
    if reset:
        lam[:] = 0.0


@kernel(inline="always")
def _end(P, x, grid_offset, slot_edge, lam, lambdas, keeps_lambda):
    """Positions back; XPBD's multipliers into model.edges order (PBD keeps none)."""
    for p in range(grid_offset.shape[0]):
        g = grid_offset[p]
        x[p, 0] = P[0, g]
        x[p, 1] = P[1, g]
        x[p, 2] = P[2, g]
    if keeps_lambda:
        for s in range(slot_edge.shape[0]):
            if slot_edge[s] >= 0:
                lambdas[slot_edge[s]] = lam[s]


@kernel(_nrt=False)
def sweep_grid_colors(x, alive, lambdas, P, W, grid_offset, chunks, color_chunks, slot_edge,
                      edge_slot, rest, alive_seen, slot_alive, lam, nx, width, block, alpha_t,
                      alpha_slots, fresh, iterations):
    """`iterations` passes of coloured Gauss-Seidel over the grid, one thread, skipping torn
    constraints (alive[e] == 0). `lam` and `slot_alive` are scratch in slot order; XPBD's λ
    of this substep end in `lambdas`."""
    keeps_lambda = alpha_slots.shape[0] > 0 or alpha_t != 0.0
    _begin(x, alive, P, grid_offset, edge_slot, alive_seen, slot_alive, lam,
           keeps_lambda and fresh)
    for _ in range(iterations):
        for c in range(NUM_COLORS):
            for q in range(color_chunks[c], color_chunks[c + 1]):
                _project_chunk(P, W, rest, slot_alive, lam, chunks, q, alpha_t, alpha_slots, nx,
                               width, block)
    _end(P, x, grid_offset, slot_edge, lam, lambdas, keeps_lambda)


@kernel(parallel=True, _nrt=False)
def sweep_grid_colors_parallel(x, alive, lambdas, P, W, grid_offset, chunks, color_chunks,
                               slot_edge, edge_slot, rest, alive_seen, slot_alive, lam, nx,
                               width, block, alpha_t, alpha_slots, fresh, iterations):
    """The same sweeps with each colour's chunks split across threads (a barrier per
    colour)."""
    keeps_lambda = alpha_slots.shape[0] > 0 or alpha_t != 0.0
    _begin(x, alive, P, grid_offset, edge_slot, alive_seen, slot_alive, lam,
           keeps_lambda and fresh)
    for _ in range(iterations):
        for c in range(NUM_COLORS):
            for q in prange(color_chunks[c], color_chunks[c + 1]):
                _project_chunk(P, W, rest, slot_alive, lam, chunks, q, alpha_t, alpha_slots, nx,
                               width, block)
    _end(P, x, grid_offset, slot_edge, lam, lambdas, keeps_lambda)


NO_SLOT_ALPHAS = np.zeros(0)  # `alpha_slots` of the scalar path: one α̃ for every pair


def sweep(kernel_fn, plan: SweepPlan, scratch: SweepScratch, x, alive, lambdas, alpha_t,
          iterations, alpha_slots: np.ndarray = NO_SLOT_ALPHAS, fresh: bool = True) -> None:
    """Runs `kernel_fn` (one of the two above) with `plan`'s arrays and a solver's scratch
    (`plan.scratch()`, kept from call to call). `alpha_slots` (from `slot_alphas`) gives
    each pair its own α̃ in place of `alpha_t`; `fresh` = False goes on with the λ of the
    last call (more passes of the same substep, between other constraints' passes)."""
    kernel_fn(x, alive, lambdas, plan.positions, plan.inv_mass, plan.grid_offset, plan.chunks,
              plan.color_chunks, plan.slot_edge, plan.edge_slot, plan.rest, scratch.alive_seen,
              scratch.slot_alive, scratch.lam, plan.nx, plan.width, plan.block, alpha_t,
              alpha_slots, fresh, iterations)


def slot_alphas(plan: SweepPlan, alpha_tilde: np.ndarray) -> np.ndarray:
    """Per-constraint α̃ (model.edges order) in slot order; slots without a constraint get
    1 (their `alive` is 0, so it is never used)."""
    out = np.ones(plan.slots)
    real = plan.slot_edge >= 0
    out[real] = np.asarray(alpha_tilde, dtype=np.float64)[plan.slot_edge[real]]
    return out
