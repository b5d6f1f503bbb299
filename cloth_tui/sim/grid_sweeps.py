"""Colour sweeps over the regular grid: the XPBD projection of xpbd.py without index gathers.

Every constraint of the sheet joins grid particle (i, j) to (i + di, j + dj) for one of six
offsets, and model.py's 12 colours split each offset by the parity of a row or column.
Positions are copied once per call into a structure-of-arrays grid P[3, n, 4·⌈n/4⌉] (and
back at the end) whose rows hold their columns in four lanes by j mod 4: column j sits at
(j mod 4)·⌈n/4⌉ + j div 4. Every pair of a colour's row then joins element m of one lane to
element m (or m ± 1) of another, even along a row, where the plain layout's stride-2 pairs did
not vectorise (measured 150 against 450 M projections/s); the RUNS of a row that continue one
another in memory are swept as one loop. Inside a colour, build_model keeps the constraints in
the order the sweeps visit them (`sweep_order`: by row, then run, then along the run), so rest
lengths, multipliers λ and anything else kept per constraint in model.edges order are read
contiguously too, and the branch-free update runs four or eight pairs to an instruction.

Rows of one colour share no particle, so the parallel kernel splits each colour's rows across
threads. Colours absent from the model (a family switched off) have start −1.
"""

from __future__ import annotations

import math

import numpy as np
from numba import prange

from .jit import kernel

NUM_COLORS = 12
# (di, dj) of each colour's constraints; colour 2k and 2k+1 share an offset
OFFSETS = ((0, 1), (0, 1), (1, 0), (1, 0), (1, 1), (1, 1), (1, -1), (1, -1),
           (0, 2), (0, 2), (2, 0), (2, 0))
COINCIDENT = 1e-12  # m: ends closer than this have no direction of their own
LANES = 4
# The runs of each colour's rows, in sweep order: (lane of a, lane of b, b's step along the
# lane); column j = 4m + lane. Along-a-row colours choose their columns by the lanes they use.
RUNS = np.array([
    [(0, 1, 0), (2, 3, 0), (0, 0, 0), (0, 0, 0)],  # 0: structural along a row, j even
    [(1, 2, 0), (3, 0, 1), (0, 0, 0), (0, 0, 0)],  # 1: j odd
    [(0, 0, 0), (1, 1, 0), (2, 2, 0), (3, 3, 0)],  # 2, 3: down a column
    [(0, 0, 0), (1, 1, 0), (2, 2, 0), (3, 3, 0)],
    [(0, 1, 0), (1, 2, 0), (2, 3, 0), (3, 0, 1)],  # 4, 5: shear (i, j)–(i+1, j+1)
    [(0, 1, 0), (1, 2, 0), (2, 3, 0), (3, 0, 1)],
    [(1, 0, 0), (2, 1, 0), (3, 2, 0), (0, 3, -1)],  # 6, 7: shear (i, j+1)–(i+1, j)
    [(1, 0, 0), (2, 1, 0), (3, 2, 0), (0, 3, -1)],
    [(0, 2, 0), (1, 3, 0), (0, 0, 0), (0, 0, 0)],  # 8: bending along a row, j mod 4 ∈ {0, 1}
    [(2, 0, 1), (3, 1, 1), (0, 0, 0), (0, 0, 0)],  # 9: j mod 4 ∈ {2, 3}
    [(0, 0, 0), (1, 1, 0), (2, 2, 0), (3, 3, 0)],  # 10, 11: bending down a column
    [(0, 0, 0), (1, 1, 0), (2, 2, 0), (3, 3, 0)],
], dtype=np.int64)
NUM_RUNS = np.array([2, 2, 4, 4, 4, 4, 4, 4, 2, 2, 4, 4], dtype=np.int64)


@kernel(inline="always")
def lane_width(n):
    """Elements per lane: ⌈n/4⌉."""
    return (n + LANES - 1) // LANES


def lane_grid(n: int) -> np.ndarray:
    """Scratch positions for the sweeps, P[3, n, 4·⌈n/4⌉]: column j of a row at
    (j mod 4)·⌈n/4⌉ + j div 4."""
    return np.empty((3, n, LANES * lane_width(n)))


def lane_masses(inv_mass: np.ndarray, n: int) -> np.ndarray:
    """Inverse masses in the sweeps' lane layout, W[n, 4·⌈n/4⌉] (padding 0)."""
    w = np.zeros((n, LANES * lane_width(n)))
    w[:, :n] = inv_mass.reshape(n, n)
    return np.ascontiguousarray(
        w.reshape(n, lane_width(n), LANES).transpose(0, 2, 1).reshape(n, -1))


def color_starts(edges: np.ndarray, color_offsets: np.ndarray, n: int) -> np.ndarray:
    """Where each of the 12 grid colours starts in `edges` (−1 if absent). ValueError unless
    `edges` are exactly the sweeps' order (`sweep_order`), which build_model's are."""
    starts = np.full(NUM_COLORS, -1, np.int64)
    for lo in color_offsets[:-1]:
        a, b = int(edges[lo, 0]), int(edges[lo, 1])
        ia, ja, d = a // n, a % n, (b // n - a // n, b % n - a % n)
        if d not in OFFSETS:
            raise ValueError(f"constraint ({a}, {b}) does not join grid neighbours")
        kind = OFFSETS.index(d)
        line = ja if kind in (0, 1, 8, 9) else ia  # the column or row its parity counts
        starts[kind + (line if kind < 8 else line // 2) % 2] = lo
    present = [c for c in range(NUM_COLORS) if starts[c] >= 0]
    if not np.array_equal(edges, sweep_order(n, present)):
        raise ValueError("the constraints are not in the grid sweeps' order")
    return starts


def sweep_order(n: int, colors: list[int]) -> np.ndarray:
    """The (a, b) pairs of `colors`, in the order the sweeps visit them (NumPy, written
    apart from the kernels' index arithmetic, as a check of both): rows of a colour in
    turn, in each row the runs of RUNS, along each run the columns in increasing order."""
    out = [np.zeros((0, 2), np.int64)]
    for c in colors:
        di, dj = OFFSETS[c]
        p = c % 2
        rows = np.arange(n - di)
        if 2 <= c < 8:
            rows = rows[rows % 2 == p]
        elif c >= 10:
            rows = rows[(rows // 2) % 2 == p]
        lo, hi = max(0, -dj), n - 1 - max(0, dj)  # columns of first particles
        cols_a, cols_b = [], []
        for qa, qb, dm in RUNS[c, :NUM_RUNS[c]]:
            ja = np.arange(lo, hi + 1)
            ja = ja[ja % LANES == qa]
            cols_a.append(ja)
            cols_b.append(LANES * (ja // LANES + dm) + qb)
        ja, jb = np.concatenate(cols_a), np.concatenate(cols_b)
        a = (rows[:, None] * n + ja[None, :]).ravel()
        b = ((rows[:, None] + di) * n + jb[None, :]).ravel()
        out.append(np.stack([a, b], axis=1))
    return np.concatenate(out).astype(np.int64)


@kernel(inline="always")
def rows_of(c, n):
    """Grid rows holding colour c's constraints."""
    p = c % 2
    if c < 2 or c >= 8 and c < 10:
        return n
    if c < 8:
        return (n - 1 - p + 1) // 2  # rows p, p+2, … ≤ n−2
    # rows i ≤ n−3 with (i // 2) % 2 == p: 2p, 2p+1, 2p+4, 2p+5, …
    last = n - 3 - 2 * p
    if last < 0:
        return 0
    return 2 * (last // 4) + min(last % 4, 1) + 1


@kernel(inline="always")
def row_length(c, n):
    """Constraints of colour c in one of its rows."""
    p = c % 2
    if c < 2:
        return max(0, (n - 1 - p + 1) // 2)  # columns p, p+2, … ≤ n−2
    if c < 4:
        return n
    if c < 8:
        return n - 1
    if c < 10:
        last = n - 3 - 2 * p  # columns j ≤ n−3 with (j // 2) % 2 == p
        if last < 0:
            return 0
        return 2 * (last // 4) + min(last % 4, 1) + 1
    return n


@kernel(inline="always")
def coincident_direction(a, b):
    """The separation (length COINCIDENT) given to constraint a–b when its ends coincide and
    have no direction of their own: any fixed, pair-dependent direction will do, so a crushed
    sheet unfolds instead of staying collapsed. One rule for the plain loop (xpbd.py) and the
    sweeps, so both unfold a sheet the same way."""
    dx = math.sin(1.3 * a + 7.1 * b)
    dy = math.cos(3.7 * a - 1.9 * b)
    dz = math.sin(2.3 * a + 0.7 * b + 1.0)
    scale = COINCIDENT / math.sqrt(dx * dx + dy * dy + dz * dz)
    return dx * scale, dy * scale, dz * scale


@kernel(inline="always")
def _pair(xa, ya, za, wa_row, ja, xb, yb, zb, wb_row, jb, rest, alive, lam, e, alpha_t, a,
          b):
    """One projection (xpbd.py's update) between element ja of one lane and jb of another:
    particles a and b of the sheet. Branch-free, so a run
    vectorises: a pinned or torn pair (alive[e] == 0, tearing.py) gets zero correction
    instead of an early exit. Coincident ends
    (no direction of their own) are left to `_crushed_pair`. λ is always written; PBD
    passes a scratch array."""
    wa = wa_row[ja]
    wb = wb_row[jb]
    dx = xb[jb] - xa[ja]
    dy = yb[jb] - ya[ja]
    dz = zb[jb] - za[ja]
    d2 = dx * dx + dy * dy + dz * dz
    crushed = d2 < COINCIDENT * COINCIDENT
    d = math.sqrt(1.0 if crushed else d2)
    lam_e = lam[e]
    s = (rest[e] - d - alpha_t * lam_e) / (d * (wa + wb + alpha_t)) if wa + wb > 0.0 else 0.0
    s = 0.0 if crushed or not alive[e] else s
    xa[ja] -= wa * s * dx
    ya[ja] -= wa * s * dy
    za[ja] -= wa * s * dz
    xb[jb] += wb * s * dx
    yb[jb] += wb * s * dy
    zb[jb] += wb * s * dz
    lam[e] = lam_e + s * d
    return 1 if crushed and alive[e] else 0  # left for `_crushed_pair`


@kernel(inline="always")
def _crushed_pair(xa, ya, za, wa_row, ja, xb, yb, zb, wb_row, jb, rest, alive, lam, e,
                  alpha_t, a, b):
    """The pairs `_pair` left: ends closer than COINCIDENT separate along xpbd.py's fixed,
    pair-dependent direction, so a crushed sheet unfolds exactly as with the plain loop.
    Pairs of one colour share no particle, so doing these after the rest of their row
    changes nothing."""
    wa = wa_row[ja]
    wb = wb_row[jb]
    dx = xb[jb] - xa[ja]
    dy = yb[jb] - ya[ja]
    dz = zb[jb] - za[ja]
    if alive[e] and wa + wb > 0.0 and dx * dx + dy * dy + dz * dz < COINCIDENT * COINCIDENT:
        dx, dy, dz = coincident_direction(a, b)
        d = COINCIDENT
        s = (rest[e] - d - alpha_t * lam[e]) / (d * (wa + wb + alpha_t))
        xa[ja] -= wa * s * dx
        ya[ja] -= wa * s * dy
        za[ja] -= wa * s * dz
        xb[jb] += wb * s * dx
        yb[jb] += wb * s * dy
        zb[jb] += wb * s * dz
        lam[e] += s * d
    return 0


@kernel(inline="always")
def _run(pair, xa, ya, za, wa, xb, yb, zb, wb, rest, alive, lam, alpha_t, row_a, row_b, fa,
         fb, width):
    """`pair` along one contiguous run; a and b's particle indices only for coincident
    pairs (row start + column, the column recovered from the lane position)."""
    left = 0
    for t in range(xa.shape[0]):
        left += pair(xa, ya, za, wa, t, xb, yb, zb, wb, t, rest, alive, lam, t, alpha_t,
                     row_a + _column(fa + t, width), row_b + _column(fb + t, width))
    return left


@kernel(inline="always")
def _column(f, width):
    return LANES * (f % width) + f // width


@kernel(inline="always")
def _project_row(pair, P, W, rest, alive, lam, starts, c, r, n, alpha_t):
    """Runs `pair` on every constraint of row r of colour c (rows of one colour are
    independent), run by run (RUNS). Returns what the pairs return: how many coincident
    pairs were left."""
    left = 0
    r = np.int64(r)  # a prange index may be unsigned: int64 arithmetic, no float mixing
    p = c % 2
    e = starts[c] + r * row_length(c, n)
    if c < 2 or c >= 8 and c < 10:
        ia = ib = r
    elif c < 10:
        ia, ib = p + 2 * r, p + 2 * r + 1
    else:
        ia = 4 * (r // 2) + 2 * p + r % 2
        ib = ia + 2
    lo = 1 if c == 6 or c == 7 else 0  # columns of the first particles
    hi = n - 2 if c < 2 or c == 4 or c == 5 else n - 3 if c == 8 or c == 9 else n - 1
    width = lane_width(n)
    xa, ya, za, wa = P[0, ia], P[1, ia], P[2, ia], W[ia]
    xb, yb, zb, wb = P[0, ib], P[1, ib], P[2, ib], W[ib]
    fa = fb = count = 0  # the current run: first elements of a and b in the row, length
    na = nb = more = 0
    for k in range(NUM_RUNS[c] + 1):
        if k < NUM_RUNS[c]:
            qa, qb, dm = RUNS[c, k, 0], RUNS[c, k, 1], RUNS[c, k, 2]
            m0 = max(0, (lo - qa + LANES - 1) // LANES)
            more = (hi - qa) // LANES - m0 + 1
            if more <= 0:
                continue
            na, nb = qa * width + m0, qb * width + m0 + dm
            if count and na == fa + count and nb == fb + count:
                count += more  # this run continues the last in memory: one longer loop
                continue
        if count:
            left += _run(pair, xa[fa:fa + count], ya[fa:fa + count], za[fa:fa + count],
                         wa[fa:fa + count], xb[fb:fb + count], yb[fb:fb + count],
                         zb[fb:fb + count], wb[fb:fb + count], rest[e:e + count],
                         alive[e:e + count], lam[e:e + count], alpha_t, ia * n, ib * n, fa,
                         fb, width)
            e += count
        if k < NUM_RUNS[c]:
            fa, fb, count = na, nb, more
    return left


@kernel(inline="always")
def _gather(x, P, n):
    width = lane_width(n)
    for i in range(n):
        for j in range(n):
            for a in range(3):
                P[a, i, (j % LANES) * width + j // LANES] = x[i * n + j, a]


@kernel(inline="always")
def _scatter(P, x, n):
    width = lane_width(n)
    for i in range(n):
        for j in range(n):
            for a in range(3):
                x[i * n + j, a] = P[a, i, (j % LANES) * width + j // LANES]


@kernel(_nrt=False)
def sweep_grid_colors(x, W, rest, alive, lam, starts, alpha_t, iterations, P):
    """`iterations` passes of coloured Gauss-Seidel over the grid, one thread, skipping torn
    constraints (alive[e] == 0). λ is reset: it accumulates over one substep's passes, and
    only for XPBD (α > 0)."""
    n = W.shape[0]
    lam[:] = 0.0
    _gather(x, P, n)
    for _ in range(iterations):
        for c in range(NUM_COLORS):
            if starts[c] < 0:
                continue
            for r in range(rows_of(c, n)):
                if _project_row(_pair, P, W, rest, alive, lam, starts, c, r, n, alpha_t):
                    _project_row(_crushed_pair, P, W, rest, alive, lam, starts, c, r, n,
                                 alpha_t)
    _scatter(P, x, n)


@kernel(parallel=True, _nrt=False)
def sweep_grid_colors_parallel(x, W, rest, alive, lam, starts, alpha_t, iterations, P):
    """The same sweeps with each colour's rows split across threads (a barrier per colour)."""
    n = W.shape[0]
    lam[:] = 0.0
    _gather(x, P, n)
    for _ in range(iterations):
        for c in range(NUM_COLORS):
            if starts[c] < 0:
                continue
            for r in prange(rows_of(c, n)):
                if _project_row(_pair, P, W, rest, alive, lam, starts, c, r, n, alpha_t):
                    _project_row(_crushed_pair, P, W, rest, alive, lam, starts, c, r, n,
                                 alpha_t)
    _scatter(P, x, n)
