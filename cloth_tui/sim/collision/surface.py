"""The sheet's surface as a mesh: vertex normals and texture coordinates of the particle grid.
The renderer draws with them every frame and the bake writes them."""

from __future__ import annotations

import math

import numpy as np

from ..jit import kernel


@kernel()
def accumulate_vertex_normals(points, triangles, out):
    """Area-weighted vertex normals into `out` (n, 3), unit length; a vertex whose triangles
    have no area gets (0, 1, 0). Compiled and in place: the renderer calls it every frame on
    up to 65k points, where the NumPy version cost 10 ms and allocated ~20 MB."""
    out[:] = 0.0
    for t in range(triangles.shape[0]):
        i, j, k = triangles[t, 0], triangles[t, 1], triangles[t, 2]
        ux = points[j, 0] - points[i, 0]
        uy = points[j, 1] - points[i, 1]
        uz = points[j, 2] - points[i, 2]
        vx = points[k, 0] - points[i, 0]
        vy = points[k, 1] - points[i, 1]
        vz = points[k, 2] - points[i, 2]
        # the cross product's length is twice the area: larger triangles weigh more
        nx = uy * vz - uz * vy
        ny = uz * vx - ux * vz
        nz = ux * vy - uy * vx
        for v in (i, j, k):
            out[v, 0] += nx
            out[v, 1] += ny
            out[v, 2] += nz
    for v in range(out.shape[0]):
        length = math.sqrt(out[v, 0] ** 2 + out[v, 1] ** 2 + out[v, 2] ** 2)
        if length < 1e-20:
            out[v, 0], out[v, 1], out[v, 2] = 0.0, 1.0, 0.0
        else:
            out[v, 0] /= length
            out[v, 1] /= length
            out[v, 2] /= length


def vertex_normals(points: np.ndarray, triangles: np.ndarray,
                   out: np.ndarray | None = None) -> np.ndarray:
    """Area-weighted vertex normals (smooth shading), unit length; zero-area stays (0, 1, 0).
    With `out` (n, 3, float32 or float64, C-contiguous) they are written there."""
    if out is None:
        out = np.empty((len(points), 3))
    accumulate_vertex_normals(np.ascontiguousarray(points, dtype=np.float64),
                              np.ascontiguousarray(triangles, dtype=np.int64), out)
    return out


def thinned_rows(n: int, stride: int) -> np.ndarray:
    """Every `stride`-th of n rows (or columns) of a grid, the last one always included."""
    return np.unique(np.r_[np.arange(0, n, max(1, int(stride))), n - 1]).astype(np.int64)


def grid_cell_triangles(nx: int, rows: np.ndarray, cols: np.ndarray) -> np.ndarray:
    """Two triangles per cell of the sub-grid `rows` × `cols` of a particle grid nx wide, as
    particle indices, in the model's pattern and winding (model.grid_triangles is the case
    rows = 0..nz−1, cols = 0..nx−1), so normals point the same way at any thinning."""
    idx = rows[:, None] * nx + cols[None, :]
    a, b, c, d = idx[:-1, :-1], idx[:-1, 1:], idx[1:, :-1], idx[1:, 1:]
    t1 = np.stack([a, c, b], axis=-1).reshape(-1, 3)
    t2 = np.stack([b, c, d], axis=-1).reshape(-1, 3)
    return np.concatenate([t1, t2]).astype(np.int64)


def grid_uv(nx: int, nz: int, width: float, length: float) -> np.ndarray:
    """Texture coordinates of the nz-row, nx-column particle grid of a width × length sheet.
    The image spans the longer side once and keeps its proportions: the shorter side shows
    the middle part of the image (a 2:1 sheet the middle half), rather than the whole image
    squashed, and needs no texture wrapping, which renderers and USD readers do not agree
    on. A square shows the whole image once."""
    long_side = max(width, length)
    u_span, v_span = width / long_side, length / long_side
    u = (0.5 - u_span / 2) + u_span * np.linspace(0.0, 1.0, nx)
    v = (0.5 - v_span / 2) + v_span * np.linspace(0.0, 1.0, nz)
    vv, uu = np.meshgrid(v, u, indexing="ij")
    return np.stack([uu.ravel(), 1.0 - vv.ravel()], axis=1)
