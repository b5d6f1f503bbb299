"""The sheet's surface as a mesh: vertex normals and texture coordinates of the particle grid.
NumPy only; the renderer draws with them and the bake writes them."""

from __future__ import annotations

import numpy as np


def vertex_normals(points: np.ndarray, triangles: np.ndarray) -> np.ndarray:
    """Area-weighted vertex normals (smooth shading), unit length; zero-area stays (0, 1, 0)."""
    a, b, c = points[triangles[:, 0]], points[triangles[:, 1]], points[triangles[:, 2]]
    face = np.cross(b - a, c - a)
    n = len(points)
    out = np.empty((n, 3))
    flat = triangles.ravel()
    for k in range(3):  # bincount is several times faster than np.add.at
        out[:, k] = np.bincount(flat, weights=np.repeat(face[:, k], 3), minlength=n)
    length = np.linalg.norm(out, axis=1)
    bad = length < 1e-20
    out[bad] = (0.0, 1.0, 0.0)
    length[bad] = 1.0
    return out / length[:, None]


def grid_uv(n: int) -> np.ndarray:
    """Texture coordinates of the n×n particle grid: the whole image once across the sheet."""
    u = np.linspace(0.0, 1.0, n)
    vv, uu = np.meshgrid(u, u, indexing="ij")
    return np.stack([uu.ravel(), 1.0 - vv.ravel()], axis=1)
