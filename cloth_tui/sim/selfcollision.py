"""Self-collision: keeps particles of the sheet apart.

Any two particles closer than the collision distance D = COLLISION_FRACTION × grid spacing
are pushed apart to D, each moving in proportion to its inverse mass (pinned ones do not
move). D is below the rest distance of every grid pair (≥ 1 spacing), so a flat sheet at rest
has no contacts; it is above half a cell diagonal (0.707 spacing), so a particle cannot slip
through the middle of a cell of another layer. Pairs the constraints already govern (the
structural, shear and bending stencil: |di|, |dj| ≤ 1, or 2 apart in a row or column) are
skipped: their distance is the constraints' business.

Two detectors list the same pairs (tested): `find_pairs_naive`, O(N²), the reference; and
`find_pairs_hash`, a sparse spatial hash of cell size 2D rebuilt every substep (counting
sort into a table of ~2N buckets, then each particle looks at the 2×2×2 cells nearest it), O(N).
`resolve_pairs` then projects the listed pairs once per substep (Gauss-Seidel).
"""

from __future__ import annotations

import math

import numpy as np
from numba import njit

COLLISION_FRACTION = 0.8  # D / spacing


@njit(nogil=True, cache=True, fastmath=True, inline="always")
def _governed(a, b, n):
    """Whether particles a, b are a constraint-stencil pair of the n×n grid."""
    di = abs(a // n - b // n)
    dj = abs(a % n - b % n)
    return (di <= 1 and dj <= 1) or (di == 0 and dj == 2) or (dj == 0 and di == 2)


@njit(nogil=True, cache=True, fastmath=True)
def find_pairs_naive(x, n, dist, pairs):
    """All non-stencil pairs (i < j) closer than `dist`, written to `pairs`. Returns how many
    there are; if that exceeds len(pairs) only the first len(pairs) were written."""
    d2max = dist * dist
    count = 0
    cap = pairs.shape[0]
    for i in range(x.shape[0]):
        for j in range(i + 1, x.shape[0]):
            dx = x[j, 0] - x[i, 0]
            dy = x[j, 1] - x[i, 1]
            dz = x[j, 2] - x[i, 2]
            if dx * dx + dy * dy + dz * dz < d2max and not _governed(i, j, n):
                if count < cap:
                    pairs[count, 0] = i
                    pairs[count, 1] = j
                count += 1
    return count


@njit(nogil=True, cache=True, fastmath=True, inline="always")
def _bucket(ix, iy, iz, mask):
    h = (ix * 92837111) ^ (iy * 689287499) ^ (iz * 283923481)
    return abs(h) & mask


@njit(nogil=True, cache=True, fastmath=True)
def build_hash(x, inv_cell, mask, cell_start, cell_particles, cells):
    """Counting sort of particles into buckets: bucket b holds
    cell_particles[cell_start[b]:cell_start[b+1]]. `cells` keeps each particle's integer cell."""
    cell_start[:] = 0
    for i in range(x.shape[0]):
        ix = int(math.floor(x[i, 0] * inv_cell))
        iy = int(math.floor(x[i, 1] * inv_cell))
        iz = int(math.floor(x[i, 2] * inv_cell))
        cells[i, 0] = ix
        cells[i, 1] = iy
        cells[i, 2] = iz
        cell_start[_bucket(ix, iy, iz, mask)] += 1
    total = 0
    for b in range(cell_start.shape[0]):  # exclusive prefix sums → bucket ends, then starts
        total += cell_start[b]
        cell_start[b] = total
    for i in range(x.shape[0]):
        b = _bucket(cells[i, 0], cells[i, 1], cells[i, 2], mask)
        cell_start[b] -= 1
        cell_particles[cell_start[b]] = i


@njit(nogil=True, cache=True, fastmath=True)
def find_pairs_hash(x, n, dist, inv_cell, mask, cell_start, cell_particles, cells, pairs):
    """The same pairs as find_pairs_naive (order aside), in O(N): build the hash (cell size
    1/inv_cell must be ≥ 2·dist), then look only at the 8 cells nearest each particle."""
    build_hash(x, inv_cell, mask, cell_start, cell_particles, cells)
    d2max = dist * dist
    count = 0
    cap = pairs.shape[0]
    for i in range(x.shape[0]):
        # Cells are 2·dist wide, so a partner closer than dist lies in the 2×2×2 cells on
        # the side of the particle's own cell it is nearer to: 8 lookups instead of 27.
        x0 = cells[i, 0] - (1 if x[i, 0] * inv_cell - cells[i, 0] < 0.5 else 0)
        y0 = cells[i, 1] - (1 if x[i, 1] * inv_cell - cells[i, 1] < 0.5 else 0)
        z0 = cells[i, 2] - (1 if x[i, 2] * inv_cell - cells[i, 2] < 0.5 else 0)
        for cx in range(x0, x0 + 2):
            for cy in range(y0, y0 + 2):
                for cz in range(z0, z0 + 2):
                    b = _bucket(cx, cy, cz, mask)
                    for k in range(cell_start[b], cell_start[b + 1]):
                        j = cell_particles[k]
                        # j > i lists each pair once; a bucket may also hold other cells that
                        # hash alike: taking only this cell's particles finds each j once.
                        if j <= i or cells[j, 0] != cx or cells[j, 1] != cy or cells[j, 2] != cz:
                            continue
                        dx = x[j, 0] - x[i, 0]
                        dy = x[j, 1] - x[i, 1]
                        dz = x[j, 2] - x[i, 2]
                        if dx * dx + dy * dy + dz * dz < d2max and not _governed(i, j, n):
                            if count < cap:
                                pairs[count, 0] = i
                                pairs[count, 1] = j
                            count += 1
    return count


@njit(nogil=True, cache=True, fastmath=True)
def resolve_pairs(x, inv_mass, pairs, count, dist):
    """Push each listed pair apart to `dist`, mass-weighted, if still closer."""
    for k in range(count):
        a = pairs[k, 0]
        b = pairs[k, 1]
        wa = inv_mass[a]
        wb = inv_mass[b]
        w = wa + wb
        if w == 0.0:
            continue
        dx = x[b, 0] - x[a, 0]
        dy = x[b, 1] - x[a, 1]
        dz = x[b, 2] - x[a, 2]
        d2 = dx * dx + dy * dy + dz * dz
        if d2 >= dist * dist or d2 < 1e-24:
            continue
        d = math.sqrt(d2)
        s = (dist - d) / (d * w)
        x[a, 0] -= wa * s * dx
        x[a, 1] -= wa * s * dy
        x[a, 2] -= wa * s * dz
        x[b, 0] += wb * s * dx
        x[b, 1] += wb * s * dy
        x[b, 2] += wb * s * dz


class SelfCollision:
    """The self-collision effect; `method` is "naive" or "hash". Buffers are allocated once
    (the pair buffer grows, rarely, when a substep finds more pairs than it holds)."""

    def __init__(self, model, method: str, fraction: float = COLLISION_FRACTION):
        self.name = f"self_collision_{method}"
        self.method = method
        self.n = model.n
        self.inv_mass = model.inv_mass
        self.distance = fraction * model.spacing
        self.inv_cell = 0.5 / self.distance  # cells 2·D wide (see find_pairs_hash)
        num = model.num_particles
        table = 1 << max(4, int(2 * num - 1).bit_length())  # power of two ≥ 2N
        self.mask = table - 1
        self.cell_start = np.zeros(table + 1, np.int32)  # int32: half the cache traffic
        self.cell_particles = np.zeros(num, np.int32)
        self.cells = np.zeros((num, 3), np.int32)
        self.pairs = np.zeros((4 * num, 2), np.int64)
        self.count = 0

    def find_pairs(self, x: np.ndarray) -> int:
        """List the close pairs of positions x into self.pairs; returns their number."""
        while True:
            if self.method == "naive":
                count = find_pairs_naive(x, self.n, self.distance, self.pairs)
            else:
                count = find_pairs_hash(x, self.n, self.distance, self.inv_cell, self.mask,
                                        self.cell_start, self.cell_particles, self.cells,
                                        self.pairs)
            if count <= len(self.pairs):
                self.count = count
                return count
            self.pairs = np.zeros((2 * count, 2), np.int64)

    def pair_set(self, x: np.ndarray) -> set:
        """The pairs that a substep at positions x would resolve, as {(i, j), i < j}."""
        k = self.find_pairs(x)
        return {(int(a), int(b)) for a, b in self.pairs[:k]}

    def apply(self, state, h):
        count = self.find_pairs(state.x)
        resolve_pairs(state.x, self.inv_mass, self.pairs, count, self.distance)


def build_self_collision(scene, model) -> list:
    method = scene.behavior.self_collision
    return [] if method == "off" else [SelfCollision(model, method)]
