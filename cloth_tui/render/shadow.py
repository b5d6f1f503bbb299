"""The cloth's shadow on the ground, cheaply: a coarse copy of the sheet (at most 33×33 of its
particles) projected along the sun's direction onto the floor and drawn there, unlit, in the
colour of ground the sun does not reach. A planar projection is exact for a flat floor and a
directional light; PyVista's shadow maps draw the scene twice and SSAO adds passes over every
pixel, both far over the frame budget in software GL (measured in docs/rendering.md).

Untextured ground: the shadow is opaque, coloured as the ground lit by ambient and headlight
only, fogged like the ground. Textured ground: translucent black, so the texture shows."""

from __future__ import annotations

import numpy as np

from .geometry import AMBIENT, GROUND_DIFFUSE, HEADLIGHT_INTENSITY, LIGHT_DIR, fog_factor, hex_rgb
from ..sim.surface import grid_cell_triangles
from .props import FOG_FAR, FOG_NEAR

MAX_SIDE = 33          # particles per side of the coarse copy: a smooth outline, ~2k triangles
LIFT = 0.001           # m above the floor: over the ground, under the grid and the fog disc
TEXTURED_ALPHA = 0.45  # darkening over a textured ground


def coarse_grid(n: int, side: int = MAX_SIDE) -> tuple[np.ndarray, np.ndarray]:
    """Particle indices of an evenly thinned m×m copy of the n×n grid (corners kept) and its
    triangles, two per cell, indexing that copy."""
    rows = np.unique(np.round(np.linspace(0, n - 1, min(n, side))).astype(np.int64))
    m = len(rows)
    return (rows[:, None] * n + rows[None, :]).ravel(), grid_cell_triangles(m, np.arange(m))


def project_to_floor(points: np.ndarray, floor_height: float, out: np.ndarray) -> np.ndarray:
    """Each point moved along the sun's direction down to the floor (plus LIFT)."""
    drop = (points[:, 1] - floor_height) / LIGHT_DIR[1]
    np.subtract(points, drop[:, None] * LIGHT_DIR[None, :], out=out)
    out[:, 1] = floor_height + LIFT
    return out


class Shadow:
    def __init__(self, pv, plotter):
        self.pv, self.plotter = pv, plotter
        self.mesh = pv.PolyData()
        self.actor = None
        self.index = np.zeros(0, np.int64)
        self.n = -1
        self.ground = self.emissive = np.zeros(3)
        self.textured = False
        self.visible = False
        self.fog_scale = 1.0

    def update_scene(self, scene, ground_textured: bool) -> None:
        s, a = scene.scene, scene.appearance
        self.ground, self.emissive = hex_rgb(a.ground_color), hex_rgb(a.ground_emissive)
        self.textured = ground_textured
        self.fog = hex_rgb(a.fog_color)
        self.fog_scale = max(1.0, scene.cloth.size)
        self.floor_height = s.floor_height
        self.visible = bool(s.floor)
        if self.actor is not None:
            self.actor.SetVisibility(self.visible)

    def _build(self, n: int) -> None:
        if self.actor is not None:
            self.plotter.remove_actor(self.actor, render=False)
        self.index, tri = coarse_grid(n)
        m = len(self.index)
        self.mesh = self.pv.PolyData(np.zeros((m, 3), np.float32),
                                     np.c_[np.full(len(tri), 3), tri].ravel())
        self.mesh.point_data["rgba"] = np.zeros((m, 4), np.uint8)
        self.actor = self.plotter.add_mesh(self.mesh, scalars="rgba", rgba=True, lighting=False,
                                           show_scalar_bar=False, reset_camera=False)
        self._projected = np.empty((m, 3))
        self.n = n
        self.actor.SetVisibility(self.visible)

    def update(self, positions: np.ndarray, n: int, elevation_deg: float) -> None:
        """Project the sheet's `positions` (an n×n grid) for a camera `elevation_deg` high
        (the headlight, which still reaches the shadow, depends on it)."""
        if n != self.n:
            self._build(n)
        if not self.visible:
            return
        p = project_to_floor(positions[self.index], self.floor_height, self._projected)
        self.mesh.points[:] = p
        f = fog_factor(np.hypot(p[:, 0], p[:, 2]) / self.fog_scale, FOG_NEAR, FOG_FAR)[:, None]
        rgba = self.mesh.point_data["rgba"]
        if self.textured:  # translucent: the fog fades the darkening out
            rgba[:, :3] = 0
            rgba[:, 3:] = (TEXTURED_ALPHA * (1 - f) * 255 + 0.5).astype(np.uint8)
        else:  # the ground as flat_ground_light makes it, without the sun's term
            head = HEADLIGHT_INTENSITY * abs(np.sin(np.radians(elevation_deg)))
            colour = np.clip(self.ground * (AMBIENT + GROUND_DIFFUSE * head) + self.emissive,
                             0.0, 1.0)
            rgba[:, :3] = ((colour * (1 - f) + self.fog * f) * 255 + 0.5).astype(np.uint8)
            rgba[:, 3] = 255
        self.mesh.GetPoints().Modified()
        rgba.VTKObject.Modified()
        self.mesh.Modified()
