"""Self-collision: keeps particles of the sheet apart.

Any two particles closer than the collision distance D = COLLISION_FRACTION × grid spacing
are pushed apart to D, each moving in proportion to its inverse mass (pinned ones do not
move). D is below the rest distance of every grid pair (≥ 1 spacing), so a flat sheet at rest
has no contacts; it is above half a cell diagonal (0.707 spacing), so a particle cannot slip
through the middle of a cell of another layer. Pairs the constraints already govern (the
structural, shear and bending stencil: |di|, |dj| ≤ 1, or 2 apart in a row or column) are
skipped: their distance is the constraints' business. Once a tear or a cut breaks the
constraint of such a pair, nothing governs it and it collides like any other: the two lips
of a cut keep apart instead of sliding through each other. (A stencil pair whose family is
switched off has no constraint to break and stays skipped.)

Two detectors list the same pairs (tested): `find_pairs_naive`, O(N²), the reference; and
`find_pairs_hash`, a sparse spatial hash of cell size 2D rebuilt every substep (counting
sort into a table of ~2N buckets, then each particle looks at the 2×2×2 cells nearest it), O(N).
`resolve_pairs` then projects the listed pairs once per substep (Gauss-Seidel).
"""

from __future__ import annotations

import math

import numpy as np

from ..jit import kernel

COLLISION_FRACTION = 0.8  # D / spacing
FLOAT32_MARGIN = 1e-6     # relative: above float32 rounding (2⁻²⁴ ≈ 6e-8) of |coordinates|
SCREEN_SLACK = 1e-12      # m: absolute part of the float32 screen's margin
COINCIDENT = 1e-12        # m: a pair this close has no direction to be pushed apart along


# The stencil's offsets (di, dj) from the lower-numbered particle of a pair, in the order of
# stencil_constraints' columns: structural right and down, shear down-right and down-left,
# bending two right and two down.
STENCIL = ((0, 1), (1, 0), (1, 1), (1, -1), (0, 2), (2, 0))


def stencil_constraints(model) -> np.ndarray:
    """(N, 6) int64: the constraint (index into model.edges) joining particle p to p + each
    STENCIL offset, −1 where there is none (off the grid, or its family switched off)."""
    nx, num = model.nx, model.num_particles
    out = np.full((num, len(STENCIL)), -1, np.int64)
    if not model.num_constraints:
        return out
    lo, hi = model.edges.min(axis=1), model.edges.max(axis=1)
    di, dj = hi // nx - lo // nx, hi % nx - lo % nx
    for k, (a, b) in enumerate(STENCIL):
        mine = (di == a) & (dj == b)
        out[lo[mine], k] = np.flatnonzero(mine)
    return out


@kernel(inline="always")
def _governed(a, b, nx, stencil, alive):
    """Whether particles a < b are a constraint-stencil pair of the grid (rows nx particles
    long) whose constraint, if it has one, is intact."""
    di = b // nx - a // nx
    dj = b % nx - a % nx
    if di == 0 and dj == 1:
        k = 0
    elif di == 1 and dj == 0:
        k = 1
    elif di == 1 and dj == 1:
        k = 2
    elif di == 1 and dj == -1:
        k = 3
    elif di == 0 and dj == 2:
        k = 4
    elif di == 2 and dj == 0:
        k = 5
    else:
        return False
    e = stencil[a, k]
    return e < 0 or alive[e] != 0


@kernel()
def find_pairs_naive(x, nx, stencil, alive, dist, pairs):
    """All pairs (i < j) closer than `dist` that no intact constraint governs, written to
    `pairs`. Returns how many there are; if that exceeds len(pairs) only the first len(pairs)
    were written."""
    d2max = dist * dist
    count = 0
    cap = pairs.shape[0]
    for i in range(x.shape[0]):
        for j in range(i + 1, x.shape[0]):
            dx = x[j, 0] - x[i, 0]
            dy = x[j, 1] - x[i, 1]
            dz = x[j, 2] - x[i, 2]
            if dx * dx + dy * dy + dz * dz < d2max and not _governed(i, j, nx, stencil, alive):
                if count < cap:
                    pairs[count, 0] = i
                    pairs[count, 1] = j
                count += 1
    return count


@kernel(inline="always")
def _bucket(ix, iy, iz, mask, stride_z, stride_y):
    """Bucket of a cell: a grid folded into the table, (ix + Sz·iz + Sy·iy) mod T with the
    strides ≈ √T. Cells next to each other land in nearby buckets, so a sweep over the sheet
    stays in cache (a scrambling hash made every lookup a cache miss: 6× slower per particle
    at 16k particles); distinct cells that share a bucket are told apart by their exact key."""
    return (ix + stride_z * iz + stride_y * iy) & mask


@kernel(inline="always")
def _cell_key(ix, iy, iz):
    """The cell's coordinates modulo 1024, packed in an int32. Two of a particle's 8 query
    cells never agree modulo 1024, so this tells a bucket's cells apart where it matters."""
    return ((ix & 1023) << 20) | ((iy & 1023) << 10) | (iz & 1023)


@kernel()
def build_hash(x, inv_cell, mask, stride_z, stride_y, cell_start, cell_particles, sorted_key,
               sorted_x):
    """Counting sort of particles into buckets: bucket b holds particles
    cell_particles[cell_start[b]:cell_start[b+1]], whose cell keys and float32 positions are
    copied to sorted_key and sorted_x in the same order, so a bucket is read contiguously
    from a compact copy. Returns the largest |coordinate| (for the float32 error bound)."""
    cell_start[:] = 0
    big = 0.0
    for i in range(x.shape[0]):
        ix = int(math.floor(x[i, 0] * inv_cell))
        iy = int(math.floor(x[i, 1] * inv_cell))
        iz = int(math.floor(x[i, 2] * inv_cell))
        cell_start[_bucket(ix, iy, iz, mask, stride_z, stride_y)] += 1
        big = max(big, abs(x[i, 0]), abs(x[i, 1]), abs(x[i, 2]))
    total = 0
    for b in range(cell_start.shape[0]):  # prefix sums → bucket ends; filling moves them
        total += cell_start[b]           # back to the bucket starts
        cell_start[b] = total
    for i in range(x.shape[0]):
        ix = int(math.floor(x[i, 0] * inv_cell))
        iy = int(math.floor(x[i, 1] * inv_cell))
        iz = int(math.floor(x[i, 2] * inv_cell))
        b = _bucket(ix, iy, iz, mask, stride_z, stride_y)
        cell_start[b] -= 1
        k = cell_start[b]
        cell_particles[k] = i
        sorted_key[k] = _cell_key(ix, iy, iz)
        sorted_x[k, 0] = x[i, 0]
        sorted_x[k, 1] = x[i, 1]
        sorted_x[k, 2] = x[i, 2]
    return big


@kernel()
def find_pairs_hash(x, nx, stencil, alive, dist, inv_cell, mask, stride_z, stride_y, cell_start,
                    cell_particles, sorted_key, sorted_x, pairs):
    """The same pairs as find_pairs_naive (order aside), in O(N): build the hash (cell size
    1/inv_cell must be ≥ 2·dist), then look only at the 8 cells nearest each particle.
    Candidates are screened in float32 with a margin above float32's rounding error, then
    decided in float64 exactly as the naive search decides them."""
    big = build_hash(x, inv_cell, mask, stride_z, stride_y, cell_start, cell_particles,
                     sorted_key, sorted_x)
    d2max = dist * dist
    screen = dist + FLOAT32_MARGIN * big + SCREEN_SLACK
    screen2 = np.float32(screen * screen)
    count = 0
    cap = pairs.shape[0]
    for i in range(x.shape[0]):  # grid order is roughly spatial order: buckets stay cached
        px = x[i, 0]
        py = x[i, 1]
        pz = x[i, 2]
        qx = np.float32(px)
        qy = np.float32(py)
        qz = np.float32(pz)
        # Cells are 2·dist wide, so a partner closer than dist lies in the 2×2×2 cells on
        # the side of the particle's own cell it is nearer to: 8 lookups instead of 27.
        x0 = int(math.floor(px * inv_cell - 0.5))
        y0 = int(math.floor(py * inv_cell - 0.5))
        z0 = int(math.floor(pz * inv_cell - 0.5))
        for cx in range(x0, x0 + 2):
            for cy in range(y0, y0 + 2):
                for cz in range(z0, z0 + 2):
                    b = _bucket(cx, cy, cz, mask, stride_z, stride_y)
                    key = _cell_key(cx, cy, cz)
                    for k in range(cell_start[b], cell_start[b + 1]):
                        # a bucket may also hold other cells that hash alike: taking only
                        # this cell's particles finds each partner once; j > i lists each
                        # pair once.
                        if sorted_key[k] != key:
                            continue
                        dx = sorted_x[k, 0] - qx
                        dy = sorted_x[k, 1] - qy
                        dz = sorted_x[k, 2] - qz
                        if dx * dx + dy * dy + dz * dz >= screen2:
                            continue
                        j = cell_particles[k]
                        if j <= i:
                            continue
                        ex = x[j, 0] - px
                        ey = x[j, 1] - py
                        ez = x[j, 2] - pz
                        if (ex * ex + ey * ey + ez * ez < d2max
                                and not _governed(i, j, nx, stencil, alive)):
                            if count < cap:
                                pairs[count, 0] = i
                                pairs[count, 1] = j
                            count += 1
    return count


@kernel()
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
        if d2 >= dist * dist or d2 < COINCIDENT * COINCIDENT:
            continue
        d = math.sqrt(d2)
        s = (dist - d) / (d * w)
        x[a, 0] -= wa * s * dx
        x[a, 1] -= wa * s * dy
        x[a, 2] -= wa * s * dz
        x[b, 0] += wb * s * dx
        x[b, 1] += wb * s * dy
        x[b, 2] += wb * s * dz


def hash_stride(table: int, cells_x: float, cells_z: float) -> int:
    """_bucket's stride between rows of cells, for a flat sheet `cells_x` × `cells_z` cells
    wide, chosen so that its cells get distinct buckets: about √table apart (a square sheet's
    rows fit side by side), or, where the sheet's rows are longer than that (a wide strip) or
    more (a long one, whose rows would wrap round the table onto each other), its own row of
    cells, the rows packed one after another. Odd: coprime with the power-of-two table, so
    rows that do wrap round it spread over every bucket."""
    row, rows = math.ceil(cells_x) + 1, math.ceil(cells_z) + 1  # a flat sheet's cells
    stride = max(math.isqrt(table), row)
    return (stride if stride * rows <= table else row) | 1


class SelfCollision:
    """The self-collision effect; `method` is "naive" or "hash". Buffers are allocated once
    (the pair buffer grows, rarely, when a substep finds more pairs than it holds)."""

    def __init__(self, model, method: str, fraction: float = COLLISION_FRACTION):
        self.name = f"self_collision_{method}"
        self.method = method
        self.nx = model.nx
        self.stencil = stencil_constraints(model)
        self.intact = np.ones(model.num_constraints, np.uint8)
        self.inv_mass = model.inv_mass
        self.distance = fraction * model.spacing
        self.inv_cell = 0.5 / self.distance  # cells 2·D wide (see find_pairs_hash)
        num = model.num_particles
        table = 1 << max(4, int(num - 1).bit_length())  # power of two ≥ N
        self.mask = table - 1
        self.stride_z = hash_stride(table, model.width * self.inv_cell,
                                    model.length * self.inv_cell)
        self.stride_y = self.stride_z + 2
        self.cell_start = np.zeros(table + 1, np.int32)  # int32: half the cache traffic
        self.cell_particles = np.zeros(num, np.int32)
        self.sorted_key = np.zeros(num, np.int32)
        self.sorted_x = np.zeros((num, 3), np.float32)  # compact: the query's working set
        self.pairs = np.zeros((4 * num, 2), np.int64)
        self.count = 0

    def find_pairs(self, x: np.ndarray, alive: np.ndarray | None = None) -> int:
        """List the close pairs of positions x into self.pairs, with the constraints' intact
        flags `alive` (None: all intact); returns their number."""
        alive = self.intact if alive is None else alive
        while True:
            if self.method == "naive":
                count = find_pairs_naive(x, self.nx, self.stencil, alive, self.distance,
                                         self.pairs)
            else:
                count = find_pairs_hash(x, self.nx, self.stencil, alive, self.distance,
                                        self.inv_cell, self.mask, self.stride_z, self.stride_y,
                                        self.cell_start, self.cell_particles,
                                        self.sorted_key, self.sorted_x, self.pairs)
            if count <= len(self.pairs):
                self.count = count
                return count
            self.pairs = np.zeros((2 * count, 2), np.int64)

    def pair_set(self, x: np.ndarray, alive: np.ndarray | None = None) -> set:
        """The pairs that a substep at positions x would resolve, as {(i, j), i < j}."""
        k = self.find_pairs(x, alive)
        return {(int(a), int(b)) for a, b in self.pairs[:k]}

    def apply(self, state, h):
        count = self.find_pairs(state.x, state.alive)
        resolve_pairs(state.x, self.inv_mass, self.pairs, count, self.distance)


def build_self_collision(scene, model) -> list:
    method = scene.behavior.self_collision
    return [] if method == "off" else [SelfCollision(model, method)]
