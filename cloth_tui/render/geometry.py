"""NumPy-only geometry for the renderer: vertex normals, grid texture coordinates, colours,
fog opacity, and picking by projection. No VTK here, so `pick` can run
on any thread and these pieces are testable without GL."""

from __future__ import annotations

import numpy as np

from ..sim.jit import kernel

LIGHT_DIR = np.array([50.0, 200.0, 100.0]) / np.linalg.norm([50.0, 200.0, 100.0])  # original's

LIGHT_COLOR = np.array([0xdf, 0xeb, 0xff]) / 255.0
AMBIENT = 0.4  # the original's 0x666666 ambient light
SUN_INTENSITY = 0.9
HEADLIGHT_INTENSITY = 0.3  # weak: only so vertical faces are never black
GROUND_DIFFUSE = 0.75


def hex_rgb(text: str) -> np.ndarray:
    """'#rrggbb' → floats in [0, 1]."""
    text = text.lstrip("#")
    return np.array([int(text[i:i + 2], 16) for i in (0, 2, 4)], dtype=np.float64) / 255.0


def triangle_edges(triangles: np.ndarray) -> np.ndarray:
    """Each edge of a triangle mesh once, (E, 2) int64."""
    e = np.concatenate([triangles[:, [0, 1]], triangles[:, [1, 2]], triangles[:, [2, 0]]])
    e.sort(axis=1)
    return np.unique(e, axis=0)


def fog_factor(r: np.ndarray, near: float, far: float) -> np.ndarray:
    return np.clip((r - near) / (far - near), 0.0, 1.0) ** 0.8


def flat_ground_light(color: np.ndarray, elevation_deg: float) -> np.ndarray:
    """What VTK's lighting makes of a level, upward-facing surface of this colour: ambient,
    plus diffuse (0.75) from the sun (intensity 0.9) and the headlight (0.3), whose angle to
    the ground is the camera's elevation. Matches the lit render to a level or two."""
    sun = SUN_INTENSITY * LIGHT_COLOR * max(0.0, LIGHT_DIR[1])
    head = HEADLIGHT_INTENSITY * abs(np.sin(np.radians(elevation_deg)))
    return color * (AMBIENT + GROUND_DIFFUSE * (sun + head))


def family_colors(family: np.ndarray) -> np.ndarray:
    """Constraint colours: structural red, shear green, bending blue (RGB uint8)."""
    palette = np.array([[230, 40, 40], [40, 200, 60], [50, 90, 240]], dtype=np.uint8)
    return palette[np.clip(family.astype(np.int64), 0, 2)]


def pick_nearest(matrix: np.ndarray, positions: np.ndarray, u: float, v: float,
                 radius: float = 0.06) -> int | None:
    """Index of the particle whose projection is nearest the image point (u, v) (0..1 from
    the top-left), or None if none lies within `radius` (a fraction of the image height).
    `matrix` is the world → clip transform of the last render; among particles about equally
    near the pointer, the one nearer the camera wins (the front layer of a fold)."""
    if matrix is None or positions is None or not len(positions):
        return None
    h = np.c_[positions, np.ones(len(positions))] @ matrix.T
    w = h[:, 3]
    front = w > 1e-9
    if not front.any():
        return None
    ndc = h[:, :3] / np.where(front, w, 1.0)[:, None]
    aspect = matrix_aspect(matrix)
    dx = (ndc[:, 0] - (2.0 * u - 1.0)) * aspect  # measure in units of the image height
    dy = ndc[:, 1] - (1.0 - 2.0 * v)
    d = np.hypot(dx, dy) * 0.5
    d[~front] = np.inf
    best = float(d.min())
    if not np.isfinite(best) or best > radius:
        return None
    near = np.flatnonzero(d <= best + 0.003)  # within ~1 px: a fold's two layers
    return int(near[np.argmin(ndc[near, 2])])


def view_plane_delta(matrix: np.ndarray, point: np.ndarray, du: float, dv: float
                     ) -> np.ndarray | None:
    """The world displacement that moves `point`'s projection by (du, dv) image fractions
    (v downward) while keeping its depth: the motion lies in the plane through `point`
    perpendicular to the view direction. `matrix` is the world → clip transform of a render.
    None if the point is behind the camera or the result is not finite."""
    if matrix is None or point is None:
        return None
    p = np.asarray(point, dtype=np.float64)
    if p.shape != (3,) or not (np.isfinite(p).all() and np.isfinite([du, dv]).all()):
        return None
    h = matrix @ np.r_[p, 1.0]
    if not h[3] > 1e-9:
        return None
    ndc = h[:3] / h[3]
    # Same NDC depth = same eye-space depth for a perspective (or orthographic) projection.
    moved = np.array([ndc[0] + 2.0 * du, ndc[1] - 2.0 * dv, ndc[2], 1.0])
    try:
        world = np.linalg.solve(matrix, moved)
    except np.linalg.LinAlgError:
        return None
    if not abs(world[3]) > 1e-12:
        return None
    delta = world[:3] / world[3] - p
    return delta if np.isfinite(delta).all() else None


def matrix_aspect(matrix: np.ndarray) -> float:
    """Width/height of the image a perspective world → clip matrix was made for (rows 0 and 1
    of the projection scale x and y by f/aspect and f)."""
    sx = np.linalg.norm(matrix[0, :3])
    sy = np.linalg.norm(matrix[1, :3])
    return float(sy / sx) if sx > 0 else 1.0


@kernel(fastmath=False)
def drawable(x, bound: float) -> bool:
    """Every coordinate finite and within ±bound, in one pass without temporaries (NumPy's
    isfinite and abs made two arrays of the sheet's size each frame)."""
    for i in range(x.shape[0]):
        for k in range(x.shape[1]):
            if not abs(x[i, k]) < bound:  # also False for NaN
                return False
    return True
