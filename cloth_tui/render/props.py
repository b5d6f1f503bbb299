"""The still parts of the picture: ground, the poles under held corners and collision
objects. Each is built once and changed in place (points, position, colours), so a long
session never piles up actors. Runs only on the render thread, like everything that touches VTK."""

from __future__ import annotations

import numpy as np

from ..sim.collision.shapes import shape_of
from .geometry import AMBIENT, GROUND_DIFFUSE, flat_ground_light, fog_factor, hex_rgb
from .pin_markers import held_particles

GROUND_RADIUS = 14.0  # m: far enough that fog hides the edge
FOG_NEAR, FOG_FAR = 2.0, 11.0  # m from the centre: the original's fog, scaled to its camera
POLE_COLOR = "#c8c8c8"
POLE_SIDES = 8
OBJECT_COLOR = "#e8e3d8"
OBJECT_OPACITY = 0.55
FAINT_OPACITY = 0.35  # a plane spans the view: fainter, so the cloth stays the subject
GRID_STEP = 0.5       # m between grid lines on the untextured ground (the texture's tile)
GRID_HALF = 6.0       # m: the grid's half-width; fog has nearly hidden the ground there
GRID_LIFT = 0.002     # m above the floor: over the ground and the cloth's shadow
GRID_SHADE = 0.8      # grid line colour = ground colour × this: subtle, but height reads
FOG_TOLERANCE = 0.004  # the ground's drawn fog within this of fog_factor (< 1 colour level)
GROUND_SECTORS = 48    # around the ground disc: its fog's rings stay round


class Ground:
    """A disc at the floor height that fades into the background colour with distance from
    the centre, so its edge vanishes, as with the original's linear fog.

    Untextured (the default), the ground is flat and every light is directional, so its
    lighting is one colour we compute here; fog is then baked into vertex colours and the
    disc is drawn unlit: the cheapest way, 2.5x faster than a lit disc under a fog layer in
    software GL. Textured, VTK ignores vertex colours, so the disc is lit and textured and a
    translucent fog disc lies just above it."""

    def __init__(self, pv, plotter):
        self.pv = pv
        self.mesh = fog_disc(pv)
        pts = np.asarray(self.mesh.points)
        self.base_xz = pts[:, [0, 2]].copy()  # for a 1 m sheet; scaled with the sheet
        self.ground_fog = fog_factor(np.hypot(pts[:, 0], pts[:, 2]), FOG_NEAR, FOG_FAR)
        self.mesh.active_texture_coordinates = pts[:, [0, 2]] / 0.5  # one tile per 0.5 m
        self.mesh.point_data["rgb"] = np.zeros((len(pts), 3), np.uint8)
        self.actor = plotter.add_mesh(self.mesh, scalars="rgb", rgb=True, show_scalar_bar=False,
                                      reset_camera=False, ambient=1.0,
                                      diffuse=GROUND_DIFFUSE, specular=0.0)
        # Only the ring where fog is non-zero: translucent pixels cost most in software GL.
        self.fog = pv.Disc(inner=FOG_NEAR, outer=GROUND_RADIUS, normal=(0, 1, 0), r_res=30,
                           c_res=96).triangulate()
        fog_pts = np.asarray(self.fog.points)
        self.fog_base_xz = fog_pts[:, [0, 2]].copy()
        self.fog_alpha = fog_factor(np.hypot(fog_pts[:, 0], fog_pts[:, 2]), FOG_NEAR, FOG_FAR)
        self.fog.point_data["rgba"] = np.zeros((len(fog_pts), 4), np.uint8)
        self.fog_actor = plotter.add_mesh(self.fog, scalars="rgba", rgba=True, lighting=False,
                                          show_scalar_bar=False, reset_camera=False)
        self.grid = grid_lines(pv, GRID_HALF, GRID_STEP)
        self.grid_base_xz = np.asarray(self.grid.points)[:, [0, 2]].copy()
        self.grid_fog = fog_factor(np.hypot(*self.grid_base_xz.T), FOG_NEAR, FOG_FAR)
        self.grid.point_data["rgb"] = np.zeros((self.grid.n_points, 3), np.uint8)
        self.grid_actor = plotter.add_mesh(self.grid, scalars="rgb", rgb=True, lighting=False,
                                           show_scalar_bar=False, reset_camera=False)
        self.textured = False
        self.colors = (np.zeros(3), np.zeros(3), np.ones(3))  # ground, emissive, fog
        self.elevation = None

    def update(self, scene, texture_image) -> None:
        s, a = scene.scene, scene.appearance
        scale = max(1.0, scene.cloth.extent())  # a big sheet gets a wider ground and fog
        self.mesh.points[:, [0, 2]] = self.base_xz * scale
        self.fog.points[:, [0, 2]] = self.fog_base_xz * scale
        self.grid.points[:, [0, 2]] = self.grid_base_xz * scale
        self.mesh.points[:, 1] = s.floor_height
        self.fog.points[:, 1] = s.floor_height + 0.003  # just above, never through the cloth
        self.grid.points[:, 1] = s.floor_height + GRID_LIFT
        for mesh in (self.mesh, self.fog, self.grid):
            mesh.GetPoints().Modified()
            mesh.Modified()
        self.textured = texture_image is not None
        self.colors = (hex_rgb(a.ground_color), hex_rgb(a.ground_emissive), hex_rgb(a.fog_color))
        self.actor.SetVisibility(bool(s.floor))
        self.fog_actor.SetVisibility(bool(s.floor) and self.textured)
        self.grid_actor.SetVisibility(bool(s.floor) and not self.textured)  # a texture shows height
        self.actor.mapper.SetScalarVisibility(not self.textured)
        self.actor.prop.lighting = self.textured
        # Unlit, VTK outputs ambient·colour + diffuse·colour: keep one term, the baked colour.
        self.actor.prop.diffuse = GROUND_DIFFUSE if self.textured else 0.0
        if self.textured:
            tex = self.pv.Texture(texture_image)
            tex.repeat = True
            tex.mipmap = True
            tex.interpolate = True
            self.actor.texture = tex
            white, emissive = np.ones(3), self.colors[1]  # a texture carries its own colour
            self.actor.prop.color = (1.0, 1.0, 1.0)
            self.actor.prop.ambient_color = tuple(np.clip(AMBIENT * white + emissive, 0, 1))
            rgba = self.fog.point_data["rgba"]
            rgba[:, :3] = (self.colors[2] * 255 + 0.5).astype(np.uint8)
            rgba[:, 3] = (self.fog_alpha * 255 + 0.5).astype(np.uint8)
            self.fog.point_data["rgba"].VTKObject.Modified()
            self.fog.Modified()
        else:
            self.actor.texture = None
            self.elevation = None  # recolour at the next shade()

    def shade(self, elevation_deg: float) -> None:
        """Bake lighting and fog into the untextured ground's colours for a camera this high
        (the headlight's share depends on it); skipped while the change is under 2°."""
        if self.textured or (self.elevation is not None
                             and abs(elevation_deg - self.elevation) < 2.0):
            return
        self.elevation = elevation_deg
        ground, emissive, fog = self.colors
        lit = np.clip(flat_ground_light(ground, elevation_deg) + emissive, 0.0, 1.0)
        f = self.ground_fog[:, None]
        rgb = self.mesh.point_data["rgb"]
        rgb[:] = ((lit[None, :] * (1 - f) + fog[None, :] * f) * 255 + 0.5).astype(np.uint8)
        self.mesh.point_data["rgb"].VTKObject.Modified()
        self.mesh.Modified()
        f = self.grid_fog[:, None]
        line = GRID_SHADE * lit
        self.grid.point_data["rgb"][:] = ((line * (1 - f) + fog * f) * 255 + 0.5).astype(np.uint8)
        self.grid.point_data["rgb"].VTKObject.Modified()
        self.grid.Modified()


def fog_ring_radii(tolerance: float = FOG_TOLERANCE) -> np.ndarray:
    """Radii (m, for a 1 m sheet) from FOG_NEAR to FOG_FAR at which the ground's fog, drawn
    linearly between them, is within `tolerance` of fog_factor: dense where the curve bends
    (just past FOG_NEAR), sparse where it is nearly straight."""
    def straight_enough(a: float, b: float) -> bool:
        r = np.linspace(a, b, 1024)
        f = fog_factor(r, FOG_NEAR, FOG_FAR)
        return np.abs(f[0] + (f[-1] - f[0]) * (r - a) / (b - a) - f).max() <= tolerance

    radii = [FOG_NEAR]
    while not straight_enough(radii[-1], FOG_FAR):
        lo, hi = radii[-1], FOG_FAR  # bisect for the farthest next ring
        for _ in range(40):
            mid = 0.5 * (lo + hi)
            lo, hi = (mid, hi) if straight_enough(radii[-1], mid) else (lo, mid)
        radii.append(lo)
    return np.array(radii + [FOG_FAR])


def fog_disc(pv):
    """The ground as a disc on y = 0 out to FOG_FAR, where the fog has reached the background
    colour (beyond, the ground would be drawn in the background's own colour): one fan to
    FOG_NEAR, inside which the ground is one colour, then rings at fog_ring_radii. Software
    GL pays for a large triangle by the tiles it crosses: 20 even rings to 14 m (1,872
    triangles) cost ~1 ms more per frame at 882×696 than these."""
    radii = fog_ring_radii()
    angles = np.linspace(0.0, 2 * np.pi, GROUND_SECTORS, endpoint=False)
    ring_xz = radii[:, None, None] * np.stack([np.cos(angles), np.sin(angles)], -1)[None]
    xz = np.concatenate([[[0.0, 0.0]], ring_xz.reshape(-1, 2)])
    points = np.c_[xz[:, 0], np.zeros(len(xz)), xz[:, 1]]
    k = np.arange(GROUND_SECTORS)
    k1 = (k + 1) % GROUND_SECTORS
    tris = [np.c_[np.zeros_like(k), 1 + k1, 1 + k]]  # the fan, facing up (+y)
    for ring in range(len(radii) - 1):
        a, b = 1 + ring * GROUND_SECTORS, 1 + (ring + 1) * GROUND_SECTORS
        tris += [np.c_[a + k, a + k1, b + k], np.c_[a + k1, b + k1, b + k]]
    tris = np.concatenate(tris)
    return pv.PolyData(points, np.c_[np.full(len(tris), 3), tris].ravel())


def grid_lines(pv, half: float, step: float):
    """Lines every `step` m across a square of half-width `half` on the plane y = 0, each cut
    into `step`-long segments so the fog baked into their colours varies along them."""
    ticks = np.arange(-half, half + 1e-9, step)
    m = len(ticks)
    along, across = np.meshgrid(ticks, ticks, indexing="ij")  # [line, point along it]
    xs = np.concatenate([across.ravel(), along.ravel()])  # lines along x, then along z
    zs = np.concatenate([along.ravel(), across.ravel()])
    points = np.c_[xs, np.zeros_like(xs), zs]
    start = np.arange(2 * m * m).reshape(2 * m, m)[:, :-1].ravel()
    segments = np.c_[np.full(len(start), 2), start, start + 1].ravel()
    return pv.PolyData(points, lines=segments)


class Poles:
    """The original's poles, from the floor up to each corner of the sheet that a pin holds
    at the start (all four in the original; the two clipped corners of a hanging sheet): a
    pole under a corner that hangs free would hold nothing."""

    def __init__(self, pv, plotter):
        self.pv = pv
        self.mesh = pv.PolyData()
        self.actor = plotter.add_mesh(self.mesh, color=POLE_COLOR, ambient=0.35, diffuse=0.8,
                                      specular=0.2, reset_camera=False)
        # Few sides, smooth-shaded (by the cylinders' own normals: add_mesh's smooth_shading
        # would draw a copy that update() never reaches), back faces culled: long thin
        # slivers spanning many of software GL's tiles cost it more than their pixels (16
        # flat sides: ~2 ms at 882×696)
        self.actor.prop.interpolation = "phong"
        self.actor.prop.culling = "back"  # closed solids: their insides never show
        self.actor.SetVisibility(False)
        self.key = None

    def update(self, scene, model) -> None:
        s = scene.scene
        tops = np.asarray(model.rest_positions)[list(held_corners(model))]
        extent = max(scene.cloth.dimensions())
        key = (tops.tobytes(), extent, s.floor_height, s.floor)
        if key == self.key:
            return
        self.key = key
        r = max(0.006, 0.008 * extent)
        poles = []
        for x, top, z in tops:
            bottom = s.floor_height if s.floor else top - 0.75 * extent
            if top - bottom > 1e-6:
                poles.append(self.pv.Cylinder(center=(x, 0.5 * (top + bottom), z),
                                              direction=(0, 1, 0), radius=r,
                                              height=top - bottom, resolution=POLE_SIDES))
        if not poles:
            self.actor.SetVisibility(False)
            return
        self.mesh.copy_from(poles[0].append_polydata(*poles[1:]) if len(poles) > 1
                            else poles[0])
        self.actor.SetVisibility(True)


def held_corners(model) -> tuple[int, ...]:
    """The particles at the sheet's four corners that a pin holds (hard or soft)."""
    nx, nz = model.nx, model.nz
    corners = sorted({0, nx - 1, (nz - 1) * nx, nz * nx - 1})
    held = set(held_particles(model).tolist())
    return tuple(i for i in corners if i in held)


class Objects:
    """Translucent collision objects, one actor per object, re-meshed only when a shape
    changes and otherwise just moved."""

    def __init__(self, pv, plotter):
        self.pv, self.plotter = pv, plotter
        self.actors: list = []
        self.shapes: list = []

    def _add(self, pose):
        shape = shape_of(pose.type)  # an unregistered type raises: no silent nothing
        mesh = shape.render_mesh(self.pv, pose.parameters)
        opacity = FAINT_OPACITY if shape.faint else OBJECT_OPACITY
        actor = self.plotter.add_mesh(mesh, color=OBJECT_COLOR, opacity=opacity,
                                      smooth_shading=shape.smooth, specular=0.3,
                                      reset_camera=False)
        actor.prop.backface_culling = False
        return actor

    def update(self, poses) -> None:
        poses = tuple(poses or ())
        while len(self.actors) > len(poses):
            self.plotter.remove_actor(self.actors.pop(), render=False)
            self.shapes.pop()
        for k, pose in enumerate(poses):
            shape = (pose.type, shape_of(pose.type).render_key(pose.parameters))
            if k == len(self.actors):
                self.actors.append(self._add(pose))
                self.shapes.append(shape)
            elif shape != self.shapes[k]:
                # a new actor, not new points in the old one: with smooth shading the mapper
                # draws a copy (with normals) that a copy_from into its dataset never reached
                # (a sphere changed to a capsule stayed a sphere)
                self.plotter.remove_actor(self.actors[k], render=False)
                self.actors[k] = self._add(pose)
                self.shapes[k] = shape
            centre = np.asarray(pose.center, dtype=np.float64)
            if np.all(np.isfinite(centre)):
                self.actors[k].SetPosition(*centre)
