"""The plain-NumPy form of the bare step, kept only as a benchmark baseline.

Same algorithm as the compiled step (Verlet with damping and gravity, the displacement clamped
to max_speed·h as a whole, coloured Gauss-Seidel projection of the three families, pins)
written with strided slices of the (nz, nx, 3) grid: every colour of `grid.grid_colors`
is one or two slice pairs, so the two forms visit constraints in the same colour order and
give the same positions.
"""

from __future__ import annotations

import numpy as np

from ..sim.model import ClothModel
from ..sim.effects.stages import damping_factor


def _slice_pairs(nx: int, nz: int, families: tuple[bool, bool, bool]) -> list[tuple]:
    """(a, b, (di, dj)) index pairs into the (nz, nx) grid, in the compiled step's colour
    order, with the offset in rows and columns that each pair spans."""
    s = slice
    out = []
    if families[0]:
        out += [((s(None), s(0, nx - 1, 2)), (s(None), s(1, nx, 2)), (0, 1)),
                ((s(None), s(1, nx - 1, 2)), (s(None), s(2, nx, 2)), (0, 1)),
                ((s(0, nz - 1, 2), s(None)), (s(1, nz, 2), s(None)), (1, 0)),
                ((s(1, nz - 1, 2), s(None)), (s(2, nz, 2), s(None)), (1, 0))]
    if families[1]:
        out += [((s(0, nz - 1, 2), s(0, nx - 1)), (s(1, nz, 2), s(1, nx)), (1, 1)),
                ((s(1, nz - 1, 2), s(0, nx - 1)), (s(2, nz, 2), s(1, nx)), (1, 1)),
                ((s(0, nz - 1, 2), s(1, nx)), (s(1, nz, 2), s(0, nx - 1)), (1, 1)),
                ((s(1, nz - 1, 2), s(1, nx)), (s(2, nz, 2), s(0, nx - 1)), (1, 1))]
    if families[2]:
        # colour (j // 2) % 2 holds j ≡ 0, 1 (mod 4) then j ≡ 2, 3: four stride-4 slices
        for r in range(4):
            out.append(((s(None), s(r, nx - 2, 4)), (s(None), s(r + 2, nx, 4)), (0, 2)))
        for r in range(4):
            out.append(((s(r, nz - 2, 4), s(None)), (s(r + 2, nz, 4), s(None)), (2, 0)))
    return out


class NumpyStep:
    """One substep of the bare scene (gravity, no floor) on plain NumPy arrays."""

    def __init__(self, model: ClothModel, h: float, iterations: int, damping: float,
                 gravity: float, max_speed: float):
        self.shape, self.h, self.iterations = model.shape, h, iterations
        self.keep = damping_factor(damping, h)
        self.g = np.array([0.0, -gravity, 0.0])
        self.max_speed = max_speed
        self.w = model.inv_mass.reshape(model.shape + (1,))
        self.moving = (model.inv_mass > 0)[:, None]
        families = tuple(bool(np.any(model.family == f)) for f in range(3))
        hz, hx = model.spacing_z, model.spacing_x
        self.pairs = [(a, b, float(np.hypot(di * hz, dj * hx)), self.w[a], self.w[b])
                      for a, b, (di, dj) in _slice_pairs(model.nx, model.nz, families)]
        self.pinned = model.pinned

    def substep(self, x: np.ndarray, x_prev: np.ndarray, v: np.ndarray,
                anchors: np.ndarray) -> None:
        h = self.h
        step = v * (self.keep * h) + self.g * (h * h)
        length = np.sqrt(np.einsum("ij,ij->i", step, step))[:, None]
        max_step = self.max_speed * h
        step *= np.where(length > max_step, max_step / np.maximum(length, 1e-300), 1.0)
        x_prev[...] = x
        x += np.where(self.moving, step, 0.0)
        grid = x.reshape(self.shape + (3,))
        for _ in range(self.iterations):
            for a, b, rest, wa, wb in self.pairs:
                d = grid[b] - grid[a]
                length = np.sqrt(np.einsum("...k,...k->...", d, d))[..., None]
                w = wa + wb
                s = np.where(w > 0, (length - rest) / np.maximum(length * w, 1e-300), 0.0)
                grid[a] += wa * s * d
                grid[b] -= wb * s * d
        x[self.pinned] = anchors
        v[...] = (x - x_prev) / h
