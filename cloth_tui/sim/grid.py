"""The sheet's regular grid, in one vocabulary: nz rows of nx particles, the sheet `width`
along x (nx columns, spacing dx) and `length` along z (nz rows, spacing dz), particle
(row i, column j) at index i·nx + j, lying flat in the x-z plane centred on the y axis.

What follows from the grid alone is built here once: rest positions, neighbour pairs (the
distance constraints' families, the fabric's kinds), render triangles and the colouring of
grid pairs that the solvers' Gauss-Seidel sweeps share (grid_sweeps.py).
"""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np

STRUCTURAL, SHEAR, BENDING = 0, 1, 2
FAMILIES = ("structural", "shear", "bending")

NUM_COLORS = 12
# (di, dj) of each colour's pairs; colour 2k and 2k+1 share an offset
OFFSETS = ((0, 1), (0, 1), (1, 0), (1, 0), (1, 1), (1, 1), (1, -1), (1, -1),
           (0, 2), (0, 2), (2, 0), (2, 0))


@dataclass(frozen=True)
class Grid:
    nx: int        # particles along x: the columns, the length of a row
    nz: int        # particles along z: the rows
    width: float   # m, along x
    length: float  # m, along z

    def __post_init__(self) -> None:
        if self.nz < 2 or self.nx < 2:
            raise ValueError(f"a grid needs at least 2×2 particles, got {self.nz}×{self.nx}")
        if not (self.width > 0 and self.length > 0):
            raise ValueError(f"grid sides must be positive, got width={self.width}, "
                             f"length={self.length}")

    @classmethod
    def of_model(cls, model) -> Grid:
        """The grid of a ClothModel."""
        return cls(nx=model.nx, nz=model.nz, width=model.width, length=model.length)

    @property
    def dx(self) -> float:
        """m, between columns."""
        return self.width / (self.nx - 1)

    @property
    def dz(self) -> float:
        """m, between rows."""
        return self.length / (self.nz - 1)

    @property
    def shape(self) -> tuple[int, int]:
        """(nz, nx): positions reshape to shape + (3,), rows first."""
        return self.nz, self.nx

    @property
    def num_particles(self) -> int:
        return self.nx * self.nz

    @property
    def area(self) -> float:
        return self.width * self.length

    def index(self, i, j):
        return np.asarray(i) * self.nx + np.asarray(j)

    def rest_positions(self, height: float = 0.0) -> np.ndarray:
        """(N, 3): the flat sheet at `height`."""
        zz, xx = np.meshgrid(np.linspace(-self.length / 2, self.length / 2, self.nz),
                             np.linspace(-self.width / 2, self.width / 2, self.nx),
                             indexing="ij")
        return np.stack([xx.ravel(), np.full(self.num_particles, height), zz.ravel()], axis=1)

    def row_share(self) -> np.ndarray:
        """(nz,) m: the length of sheet each row stands for (a border row half a cell)."""
        return _share(self.nz, self.dz)

    def col_share(self) -> np.ndarray:
        """(nx,) m: the width of sheet each column stands for."""
        return _share(self.nx, self.dx)

    def pairs(self, di: int, dj: int) -> np.ndarray:
        """(M, 2) int64: every particle (i, j) joined to (i + di, j + dj), row by row."""
        idx = np.arange(self.num_particles).reshape(self.shape)
        rows = slice(0, self.nz - di)
        a = idx[rows, max(0, -dj):self.nx - max(0, dj)]
        b = idx[di:, max(0, dj):self.nx - max(0, -dj)]
        return np.stack([a.ravel(), b.ravel()], axis=1).astype(np.int64)

    def cell_corners(self) -> np.ndarray:
        """(C, 4) int64 per cell: (i, j), (i, j+1), (i+1, j), (i+1, j+1)."""
        idx = np.arange(self.num_particles).reshape(self.shape)
        return np.stack([idx[:-1, :-1], idx[:-1, 1:], idx[1:, :-1], idx[1:, 1:]],
                        axis=-1).reshape(-1, 4).astype(np.int64)


def _share(count: int, spacing: float) -> np.ndarray:
    share = np.full(count, spacing)
    share[[0, -1]] = spacing / 2
    return share


# The (di, dj) offsets of each distance-constraint family: rows' and columns' neighbours,
# both diagonals of a cell, and two apart along a row and a column
FAMILY_OFFSETS = {STRUCTURAL: ((0, 1), (1, 0)), SHEAR: ((1, 1), (1, -1)),
                  BENDING: ((0, 2), (2, 0))}


def grid_edges(nx: int, nz: int,
               families: tuple[bool, bool, bool]) -> tuple[np.ndarray, np.ndarray]:
    """Constraint pairs of an nz-row, nx-column grid for the enabled families, and each pair's
    family."""
    grid = _topology(nx, nz)
    pairs, fam = [], []
    for f, on in enumerate(families):
        if on:
            for di, dj in FAMILY_OFFSETS[f]:
                p = grid.pairs(di, dj)
                pairs.append(p)
                fam.append(np.full(len(p), f, dtype=np.int8))
    if not pairs:
        return np.zeros((0, 2), np.int64), np.zeros(0, np.int8)
    return np.concatenate(pairs).astype(np.int64), np.concatenate(fam)


def grid_pairs(grid: Grid) -> dict[str, np.ndarray]:
    """The neighbour pairs of the grid by kind: "u" (along x), "v" (along z) and "diagonal"
    (both diagonals of every cell), each (M, 2) int64."""
    return {"u": grid.pairs(0, 1), "v": grid.pairs(1, 0),
            "diagonal": np.concatenate([grid.pairs(1, 1), grid.pairs(1, -1)])}


def grid_triangles(nx: int, nz: int) -> np.ndarray:
    """Two triangles per cell, for rendering and wind."""
    a, b, c, d = _topology(nx, nz).cell_corners().T
    # One diagonal, (i, j+1)–(i+1, j), in every cell (alternating would change images and wind)
    t1 = np.stack([a, c, b], axis=-1)
    t2 = np.stack([b, c, d], axis=-1)
    return np.concatenate([t1, t2]).astype(np.int64)


def _topology(nx: int, nz: int) -> Grid:
    """A grid of this many particles, for what depends on its topology alone."""
    return Grid(nx=nx, nz=nz, width=1.0, length=1.0)


def color_of(c: int, row_block: int, col_block: int) -> bool:
    """Whether the pairs of colour c start in block (i mod 4, j mod 4) (grid_colors' rule,
    which grid_sweeps.py lays out in blocks)."""
    p = c % 2
    if c < 2:
        return col_block % 2 == p
    if c < 8:
        return row_block % 2 == p
    if c < 10:
        return col_block // 2 == p
    return row_block // 2 == p


def grid_colors(edges: np.ndarray, nx: int) -> np.ndarray:
    """The colour (0–11) of each constraint of a grid nx particles wide: 2 per offset, by the
    parity of its first particle's row or column (of its half, for bending). No two
    constraints of one colour share a particle, so a colour can be projected in parallel
    without races (Gauss-Seidel between colours). ValueError for a constraint between far
    particles."""
    a, b = edges[:, 0], edges[:, 1]
    ia, ja, di, dj = a // nx, a % nx, b // nx - a // nx, b % nx - a % nx
    colors = np.full(len(edges), -1, np.int64)
    for kind in range(0, NUM_COLORS, 2):
        on = (di == OFFSETS[kind][0]) & (dj == OFFSETS[kind][1])
        line = ja if kind in (0, 8) else ia  # the column or row its parity counts
        colors[on] = kind + (line[on] if kind < 8 else line[on] // 2) % 2
    if (colors < 0).any():
        e = int(np.argmax(colors < 0))
        raise ValueError(f"constraint ({a[e]}, {b[e]}) does not join grid neighbours")
    return colors
