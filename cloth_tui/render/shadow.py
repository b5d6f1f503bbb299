"""The cloth's shadow on the ground, cheaply: a coarse copy of the sheet (at most 33 of its
particles along each side) projected along the sun's direction onto the floor and drawn there,
unlit, in the colour of ground the sun does not reach. A planar projection is exact for a flat
floor and a directional light; PyVista's shadow maps draw the scene twice and SSAO adds passes
over every pixel, both far over the frame budget in software GL (measured in
docs/rendering.md).

A torn sheet casts the shadow of the faces it shows (every particle, the renderer's intact
triangles): the coarse copy's cells would span its tears and shade the ground under the gap.

Untextured ground: the shadow is opaque, coloured as the ground lit by ambient and headlight
only, fogged like the ground. Textured ground: translucent black, so the texture shows."""

from __future__ import annotations

import math

import numpy as np

from .geometry import AMBIENT, GROUND_DIFFUSE, HEADLIGHT_INTENSITY, LIGHT_DIR, hex_rgb
from ..sim.jit import kernel
from ..sim.collision.surface import grid_cell_triangles
from .props import FOG_FAR, FOG_NEAR

MAX_SIDE = 33          # particles along each side of the coarse copy: smooth, ≤ 2k faces
LIFT = 0.001           # m above the floor: over the ground, under the grid and the fog disc
TEXTURED_ALPHA = 0.45  # darkening over a textured ground


def coarse_grid(nx: int, nz: int, side: int = MAX_SIDE) -> tuple[np.ndarray, np.ndarray]:
    """Particle indices of an evenly thinned copy of the nz-row, nx-column grid (at most
    `side` rows and columns, corners kept) and its triangles, two per cell, indexing that
    copy."""
    rows = np.unique(np.round(np.linspace(0, nz - 1, min(nz, side))).astype(np.int64))
    cols = np.unique(np.round(np.linspace(0, nx - 1, min(nx, side))).astype(np.int64))
    m = len(cols)
    return ((rows[:, None] * nx + cols[None, :]).ravel(),
            grid_cell_triangles(m, np.arange(len(rows)), np.arange(m)))


@kernel(fastmath=False)
def project_to_floor(points, floor_height, out):
    """Each point moved along the sun's direction down to the floor (plus LIFT)."""
    for i in range(points.shape[0]):
        drop = (points[i, 1] - floor_height) / LIGHT_DIR[1]
        for k in range(3):
            out[i, k] = points[i, k] - drop * LIGHT_DIR[k]
        out[i, 1] = floor_height + LIFT
    return out


@kernel(fastmath=False)
def cast_shadow(positions, index, floor_height, fog_scale, colour, fog, textured,
                scratch, points, rgba):
    """The coarse copy's particles (`index` into `positions`) projected onto the floor into
    `points` (the mesh's float32 array) and their colours into `rgba`, fogged by distance
    from the centre: untextured, `colour` fading into `fog`; textured, black fading out.
    One pass in place: as NumPy array expressions the per-call overhead would dominate."""
    for j in range(index.shape[0]):
        for k in range(3):
            scratch[j, k] = positions[index[j], k]
    project_to_floor(scratch, floor_height, scratch)
    for j in range(index.shape[0]):
        x, z = scratch[j, 0], scratch[j, 2]
        points[j, 0], points[j, 1], points[j, 2] = x, scratch[j, 1], z
        f = min(max((math.hypot(x, z) / fog_scale - FOG_NEAR) / (FOG_FAR - FOG_NEAR), 0.0),
                1.0) ** 0.8  # geometry.fog_factor
        if textured:  # translucent: the fog fades the darkening out
            rgba[j, 0] = rgba[j, 1] = rgba[j, 2] = 0
            rgba[j, 3] = np.uint8(TEXTURED_ALPHA * (1 - f) * 255 + 0.5)
        else:
            for k in range(3):
                rgba[j, k] = np.uint8((colour[k] * (1 - f) + fog[k] * f) * 255 + 0.5)
            rgba[j, 3] = 255


class Shadow:
    def __init__(self, pv, plotter):
        self.pv, self.plotter = pv, plotter
        self.mesh = pv.PolyData()
        self.actor = None
        self.index = np.zeros(0, np.int64)
        self.drawn = ((0, 0), 0)  # ((nx, nz), torn count) the mesh was built for
        self.ground = self.emissive = np.zeros(3)
        self.textured = False
        self.visible = False
        self.fog_scale = 1.0

    def update_scene(self, scene, ground_textured: bool) -> None:
        s, a = scene.scene, scene.appearance
        self.ground, self.emissive = hex_rgb(a.ground_color), hex_rgb(a.ground_emissive)
        self.textured = ground_textured
        self.fog = hex_rgb(a.fog_color)
        self.fog_scale = max(1.0, scene.cloth.extent())
        self.floor_height = s.floor_height
        self.visible = bool(s.floor)
        if self.actor is not None:
            self.actor.SetVisibility(self.visible)

    def _build(self, nx: int, nz: int, torn_faces: np.ndarray | None) -> None:
        if self.actor is not None:
            self.plotter.remove_actor(self.actor, render=False)
        if torn_faces is None:
            self.index, tri = coarse_grid(nx, nz)
        else:
            self.index, tri = np.arange(nx * nz, dtype=np.int64), torn_faces
        m = len(self.index)
        self.mesh = self.pv.PolyData(np.zeros((m, 3), np.float32),
                                     np.c_[np.full(len(tri), 3), tri].ravel())
        self.mesh.point_data["rgba"] = np.zeros((m, 4), np.uint8)
        self.actor = self.plotter.add_mesh(self.mesh, scalars="rgba", rgba=True, lighting=False,
                                           show_scalar_bar=False, reset_camera=False)
        self._scratch = np.empty((m, 3))
        self._points_view = self.mesh.points  # NumPy views of VTK's arrays, written in place
        self._rgba_view = self.mesh.point_data["rgba"]
        self.actor.SetVisibility(self.visible)

    def update(self, positions: np.ndarray, grid: tuple[int, int], elevation_deg: float,
               torn_faces: np.ndarray | None = None, torn: int = 0) -> None:
        """Project the sheet's `positions` (a grid of `grid` = (nx, nz) particles) for a
        camera `elevation_deg` high (the headlight, which still reaches the shadow, depends
        on it). On a torn sheet (`torn` constraints broken) the shadow is of `torn_faces`,
        the triangles drawn; rebuilt only when the grid or the torn count changes, as the
        sheet's faces are."""
        grid = (int(grid[0]), int(grid[1]))
        if (grid, torn) != self.drawn:
            self._build(*grid, torn_faces if torn else None)
            self.drawn = (grid, torn)
        if not self.visible:
            return
        # untextured: the ground as flat_ground_light makes it, without the sun's term
        head = HEADLIGHT_INTENSITY * abs(math.sin(math.radians(elevation_deg)))
        colour = np.clip(self.ground * (AMBIENT + GROUND_DIFFUSE * head) + self.emissive,
                         0.0, 1.0)
        cast_shadow(np.asarray(positions, np.float64), self.index, float(self.floor_height),
                    float(self.fog_scale), colour, self.fog, self.textured, self._scratch,
                    self._points_view, self._rgba_view)
        self.mesh.GetPoints().Modified()
        self._rgba_view.VTKObject.Modified()
        self.mesh.Modified()
