"""Colour sweeps over the regular grid: the XPBD projection of xpbd.py without index gathers.

Every constraint of the sheet joins grid particle (i, j) to (i + di, j + dj) for one of six
offsets, and model.py's 12 colours split each offset by the parity of a row or column. Inside
a colour, build_model keeps the constraints in row-major order of their first particle, so a
colour's constraints are whole rows of the grid, and constraint e of a row is the next one in
model.edges order: rest lengths, multipliers λ (and anything else kept per constraint, in
model.edges order) are read contiguously, and both particles of a row's constraints are
contiguous runs of one grid row. Positions are copied once per call into a structure-of-arrays
grid P[3, n, n] (and back at the end), so LLVM can run a row's projections four or eight to
an instruction.

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
    independently of the kernels' index arithmetic as a check of both)."""
    idx = np.arange(n * n).reshape(n, n)
    out = [np.zeros((0, 2), np.int64)]
    for c in colors:
        di, dj = OFFSETS[c]
        p = c % 2
        a = idx[:n - di, max(0, -dj):n - max(0, dj)]  # first particles of every pair
        rows, cols = np.arange(a.shape[0]), np.arange(a.shape[1]) + max(0, -dj)
        if c < 2:
            keep_r, keep_c = np.ones_like(rows, bool), cols % 2 == p
        elif c < 8:
            keep_r, keep_c = rows % 2 == p, np.ones_like(cols, bool)
        elif c < 10:
            keep_r, keep_c = np.ones_like(rows, bool), (cols // 2) % 2 == p
        else:
            keep_r, keep_c = (rows // 2) % 2 == p, np.ones_like(cols, bool)
        first = a[keep_r][:, keep_c].ravel()
        out.append(np.stack([first, first + di * n + dj], axis=1))
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
def _pair(xa, ya, za, wa_row, ja, xb, yb, zb, wb_row, jb, rest, lam, e, alpha_t, ia, ib, n):
    """One projection (xpbd.py's update) between particle ja of one grid row and jb of
    another (or the same): rows ia and ib of an n-wide grid. Branch-free, so a row
    vectorises: a pinned pair gets zero weight instead of an early exit. Coincident ends
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
    s = 0.0 if crushed else s
    xa[ja] -= wa * s * dx
    ya[ja] -= wa * s * dy
    za[ja] -= wa * s * dz
    xb[jb] += wb * s * dx
    yb[jb] += wb * s * dy
    zb[jb] += wb * s * dz
    lam[e] = lam_e + s * d
    return 1 if crushed else 0  # left for `_crushed_pair`


@kernel(inline="always")
def _crushed_pair(xa, ya, za, wa_row, ja, xb, yb, zb, wb_row, jb, rest, lam, e, alpha_t, ia,
                  ib, n):
    """The pairs `_pair` left: ends closer than COINCIDENT separate along xpbd.py's fixed,
    pair-dependent direction, so a crushed sheet unfolds exactly as with the plain loop.
    Pairs of one colour share no particle, so doing these after the rest of their row
    changes nothing."""
    wa = wa_row[ja]
    wb = wb_row[jb]
    dx = xb[jb] - xa[ja]
    dy = yb[jb] - ya[ja]
    dz = zb[jb] - za[ja]
    if wa + wb > 0.0 and dx * dx + dy * dy + dz * dz < COINCIDENT * COINCIDENT:
        a = ia * n + ja
        b = ib * n + jb
        dx = math.sin(1.3 * a + 7.1 * b)
        dy = math.cos(3.7 * a - 1.9 * b)
        dz = math.sin(2.3 * a + 0.7 * b + 1.0)
        scale = COINCIDENT / math.sqrt(dx * dx + dy * dy + dz * dz)
        dx *= scale
        dy *= scale
        dz *= scale
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
def _project_row(pair, P, W, rest, lam, starts, c, r, n, alpha_t):
    """Runs `pair` on every constraint of row r of colour c (rows of one colour are
    independent). Returns what the pairs return: how many coincident pairs were left."""
    left = 0
    r = np.int64(r)  # a prange index may be unsigned: int64 arithmetic, no float mixing
    p = c % 2
    length = row_length(c, n)
    e0 = starts[c] + r * length
    rs = rest[e0:e0 + length]
    ls = lam[e0:e0 + length]
    if c < 2 or c >= 8 and c < 10:
        ia = ib = r
    elif c < 10:
        ia, ib = p + 2 * r, p + 2 * r + 1
    else:
        ia = 4 * (r // 2) + 2 * p + r % 2
        ib = ia + 2
    xa, ya, za, wa = P[0, ia], P[1, ia], P[2, ia], W[ia]
    xb, yb, zb, wb = P[0, ib], P[1, ib], P[2, ib], W[ib]
    if c < 2:  # structural along a row: (i, j)–(i, j+1), j = p, p+2, …
        for k in range(length):
            left += pair(xa, ya, za, wa, p + 2 * k, xb, yb, zb, wb, p + 2 * k + 1, rs, ls,
                         k, alpha_t, ia, ib, n)
    elif c < 4 or c >= 10:  # structural or bending down a column
        for j in range(length):
            left += pair(xa, ya, za, wa, j, xb, yb, zb, wb, j, rs, ls, j, alpha_t, ia, ib, n)
    elif c < 6:  # shear (i, j)–(i+1, j+1)
        for j in range(length):
            left += pair(xa, ya, za, wa, j, xb, yb, zb, wb, j + 1, rs, ls, j, alpha_t,
                         ia, ib, n)
    elif c < 8:  # shear (i, j+1)–(i+1, j)
        for j in range(length):
            left += pair(xa, ya, za, wa, j + 1, xb, yb, zb, wb, j, rs, ls, j, alpha_t,
                         ia, ib, n)
    else:  # bending along a row: (i, j)–(i, j+2), j = 2p, 2p+1, 2p+4, 2p+5, …
        for k in range((length + 1) // 2):
            left += pair(xa, ya, za, wa, 4 * k + 2 * p, xb, yb, zb, wb, 4 * k + 2 * p + 2,
                         rs, ls, 2 * k, alpha_t, ia, ib, n)
        for k in range(length // 2):
            left += pair(xa, ya, za, wa, 4 * k + 2 * p + 1, xb, yb, zb, wb, 4 * k + 2 * p + 3,
                         rs, ls, 2 * k + 1, alpha_t, ia, ib, n)
    return left


@kernel(inline="always")
def _gather(x, P, n):
    for i in range(n):
        for j in range(n):
            for a in range(3):
                P[a, i, j] = x[i * n + j, a]


@kernel(inline="always")
def _scatter(P, x, n):
    for i in range(n):
        for j in range(n):
            for a in range(3):
                x[i * n + j, a] = P[a, i, j]


@kernel(_nrt=False)
def sweep_grid_colors(x, W, rest, lam, starts, alpha_t, iterations, P):
    """`iterations` passes of coloured Gauss-Seidel over the grid, one thread. λ is reset:
    it accumulates over one substep's passes, and only for XPBD (α > 0)."""
    n = W.shape[0]
    lam[:] = 0.0
    _gather(x, P, n)
    for _ in range(iterations):
        for c in range(NUM_COLORS):
            if starts[c] < 0:
                continue
            for r in range(rows_of(c, n)):
                if _project_row(_pair, P, W, rest, lam, starts, c, r, n, alpha_t):
                    _project_row(_crushed_pair, P, W, rest, lam, starts, c, r, n, alpha_t)
    _scatter(P, x, n)


@kernel(parallel=True, _nrt=False)
def sweep_grid_colors_parallel(x, W, rest, lam, starts, alpha_t, iterations, P):
    """The same sweeps with each colour's rows split across threads (a barrier per colour)."""
    n = W.shape[0]
    lam[:] = 0.0
    _gather(x, P, n)
    for _ in range(iterations):
        for c in range(NUM_COLORS):
            if starts[c] < 0:
                continue
            for r in prange(rows_of(c, n)):
                if _project_row(_pair, P, W, rest, lam, starts, c, r, n, alpha_t):
                    _project_row(_crushed_pair, P, W, rest, lam, starts, c, r, n, alpha_t)
    _scatter(P, x, n)
