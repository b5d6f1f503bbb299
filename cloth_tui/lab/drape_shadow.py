"""The Cusick specimen on the grid and the shadow the drapemeter measures.

The specimen is the union of the sheet's triangles kept whole by the cut: its outline is a
staircase, so the cut's radius is chosen on each grid for the kept triangles to cover the
disc's π·R² (the nearest a staircase gets); a fixed cut at R would make a specimen smaller
than the disc by an amount that changes with the grid, and the coefficient with it.

The shadow is the lamp's: the union of the specimen's triangles projected on the horizontal
plane and the support disc, counted on a fixed raster of pixel centres. The folds of a
draped rim overlap themselves in projection, so no polygon of the rim is its shadow."""

from __future__ import annotations

import math

import numpy as np

PIXEL = 5e-4   # m: the raster's pixel; a shadow's area is counted to well under 0.1 %
CHUNK_PIXELS = 4_000_000  # pixel tests per chunk of triangles (memory, not the answer)


def grid_coords(n: int, radius: float) -> tuple[np.ndarray, float]:
    """(n·n, 2) flat (x, z) of an n × n grid spanning the diameter 2·radius, row-major
    (row i along z, column j along x, as the sheet's particles), and the spacing."""
    h = 2 * radius / (n - 1)
    c = (np.arange(n) - (n - 1) / 2) * h
    zz, xx = np.meshgrid(c, c, indexing="ij")
    return np.column_stack([xx.ravel(), zz.ravel()]), h


def specimen_triangles(n: int, radius: float) -> tuple[np.ndarray, float]:
    """The triangles of the n × n sheet that make the specimen, and the cut radius: a
    triangle is kept when its farthest corner lies within the cut, and the cut is the one of
    the corners' radii whose kept triangles' area is nearest π·radius²."""
    from ..sim.model import grid_triangles

    xz, h = grid_coords(n, radius)
    tri = grid_triangles(n, n)
    far = np.hypot(xz[:, 0], xz[:, 1])[tri].max(axis=1)
    order = np.argsort(far, kind="stable")
    count = np.arange(1, len(order) + 1)
    best = int(np.argmin(np.abs(count * h * h / 2 - math.pi * radius ** 2)))
    cut = float(far[order[best]])
    return tri[far <= cut + 1e-12], cut


def boundary_particles(triangles: np.ndarray) -> np.ndarray:
    """The particles on the specimen's outline: on an edge only one kept triangle has."""
    e = np.sort(np.concatenate([triangles[:, [0, 1]], triangles[:, [1, 2]],
                                triangles[:, [2, 0]]]), axis=1)
    edges, counts = np.unique(e, axis=0, return_counts=True)
    return np.unique(edges[counts == 1])


def raster_frame(reach: float, pixel: float = PIXEL) -> tuple[np.ndarray, int]:
    """The raster's pixel centres along one side (a square ±reach about the middle)."""
    m = int(math.ceil(2 * reach / pixel))
    return (np.arange(m) + 0.5) * pixel - m * pixel / 2, m


def shadow_mask(xz: np.ndarray, triangles: np.ndarray, support_radius: float, reach: float,
                pixel: float = PIXEL) -> np.ndarray:
    """(m, m) bool, [row along z, column along x]: the pixels whose centres lie in a
    projected triangle or on the support disc, about (0, 0)."""
    centres, m = raster_frame(reach, pixel)
    zz, xx = np.meshgrid(centres, centres, indexing="ij")
    mask = np.hypot(xx, zz) <= support_radius
    a, b, c = xz[triangles[:, 0]], xz[triangles[:, 1]], xz[triangles[:, 2]]
    lo = np.minimum(np.minimum(a, b), c)
    hi = np.maximum(np.maximum(a, b), c)
    first = np.floor((lo - centres[0]) / pixel).astype(np.int64)
    spans = np.ceil(((hi - lo) / pixel).max(axis=1)).astype(np.int64) + 2
    by_span = np.argsort(spans, kind="stable")  # chunks of alike triangles: a box each
    s = 0
    while s < len(by_span):
        span = int(spans[by_span[min(s + 4095, len(by_span) - 1)]])
        count = max(1, min(4096, CHUNK_PIXELS // (span * span)))
        sl = by_span[s:s + count]
        span = int(spans[sl].max())
        s += count
        offsets = np.arange(span)
        cols = first[sl, 0, None] + offsets          # (t, span)
        rows = first[sl, 1, None] + offsets
        px = centres[0] + cols * pixel
        pz = centres[0] + rows * pixel
        P = np.stack(np.broadcast_arrays(px[:, None, :], pz[:, :, None]), axis=-1)
        inside = _in_triangles(P, a[sl], b[sl], c[sl])
        inside &= ((rows >= 0) & (rows < m))[:, :, None] & ((cols >= 0) & (cols < m))[:, None, :]
        t, r, q = np.nonzero(inside)
        mask[rows[t, r], cols[t, q]] = True
    return mask


def _in_triangles(P: np.ndarray, a, b, c) -> np.ndarray:
    """(t, s, s) bool: the points P (t, s, s, 2) inside triangle t (either winding; a
    triangle seen edge-on covers nothing)."""
    def side(p, q):
        d = (q - p)[:, None, None, :]
        w = P - p[:, None, None, :]
        return d[..., 0] * w[..., 1] - d[..., 1] * w[..., 0]

    s1, s2, s3 = side(a, b), side(b, c), side(c, a)
    return ((s1 >= 0) & (s2 >= 0) & (s3 >= 0)) | ((s1 <= 0) & (s2 <= 0) & (s3 <= 0))


def shadow_area(xz: np.ndarray, triangles: np.ndarray, support_radius: float, reach: float,
                pixel: float = PIXEL) -> float:
    """m²: the shadow_mask's area."""
    return float(shadow_mask(xz, triangles, support_radius, reach, pixel).sum()) * pixel ** 2
