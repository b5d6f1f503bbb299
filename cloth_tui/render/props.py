"""The still parts of the picture: ground, corner poles and collision objects. Each is built
once and changed in place (points, position, colours), so a long session never piles up
actors. Runs only on the render thread, like everything that touches VTK."""

from __future__ import annotations

import numpy as np

from .geometry import ground_colors, hex_rgb

GROUND_RADIUS = 14.0  # m: far enough that fog hides the edge
FOG_NEAR, FOG_FAR = 2.0, 11.0  # m from the centre: the original's fog, scaled to its camera
POLE_COLOR = "#c8c8c8"
OBJECT_COLOR = "#e8e3d8"
OBJECT_OPACITY = 0.55
PLANE_HALF = 1.25  # m: shown extent of an (infinite) collision plane


class Ground:
    """A disc at the floor height with per-vertex fog, optionally textured (tiled)."""

    def __init__(self, pv, plotter):
        self.pv = pv
        disc = pv.Disc(inner=0.0, outer=GROUND_RADIUS, normal=(0, 1, 0), r_res=40, c_res=96)
        disc = disc.triangulate()
        self.mesh = disc
        pts = np.asarray(disc.points)
        self.base_points = pts.copy()
        self.base_points[:, 1] = 0.0
        self.mesh.active_texture_coordinates = pts[:, [0, 2]] / 0.5  # one tile per 0.5 m
        self.mesh.point_data["rgb"] = np.zeros((len(pts), 3), np.uint8)
        self.actor = plotter.add_mesh(self.mesh, scalars="rgb", rgb=True, lighting=False,
                                      show_scalar_bar=False, reset_camera=False)
        self.texture_name = "none"

    def update(self, scene, texture_image) -> None:
        s, a = scene.scene, scene.appearance
        self.actor.SetVisibility(bool(s.floor))
        self.mesh.points[:, 1] = s.floor_height
        self.mesh.Modified()
        textured = texture_image is not None
        if textured:
            tex = self.pv.Texture(texture_image)
            tex.repeat = True
            tex.mipmap = True
            tex.interpolate = True
            self.actor.texture = tex
        else:
            self.actor.texture = None
        self.mesh.point_data["rgb"][:] = ground_colors(
            self.base_points, hex_rgb(a.ground_color), hex_rgb(a.ground_emissive),
            hex_rgb(a.fog_color), FOG_NEAR, FOG_FAR, textured)
        self.mesh.point_data.Modified()


class Poles:
    """The original's four poles at the sheet's corners, from the floor up to the sheet."""

    def __init__(self, pv, plotter):
        self.pv = pv
        self.mesh = pv.PolyData()
        self.actor = plotter.add_mesh(self.mesh, color=POLE_COLOR, ambient=0.35, diffuse=0.8,
                                      specular=0.2, reset_camera=False)
        self.key = None

    def update(self, scene) -> None:
        c, s = scene.cloth, scene.scene
        key = (c.size, c.height, s.floor_height, s.floor)
        if key == self.key:
            return
        self.key = key
        top, bottom = c.height, s.floor_height if s.floor else c.height - 0.75 * c.size
        if top - bottom <= 1e-6:
            self.actor.SetVisibility(False)
            return
        half, r = c.size / 2, max(0.006, 0.008 * c.size)
        poles = [self.pv.Cylinder(center=(x, 0.5 * (top + bottom), z), direction=(0, 1, 0),
                                  radius=r, height=top - bottom, resolution=16)
                 for x in (-half, half) for z in (-half, half)]
        self.mesh.copy_from(poles[0].append_polydata(*poles[1:]))
        self.actor.SetVisibility(True)


def _object_mesh(pv, pose):
    """Mesh of one object, centred at the origin (the actor's position places it)."""
    if pose.type == "sphere":
        return pv.Sphere(radius=pose.radius, theta_resolution=40, phi_resolution=24)
    if pose.type == "box":
        sx, sy, sz = (float(v) / 2 for v in pose.size)
        return pv.Box((-sx, sx, -sy, sy, -sz, sz))
    if pose.type == "capsule":
        return pv.Capsule(direction=tuple(pose.normal), radius=pose.radius,
                          cylinder_length=float(pose.size[1]), resolution=30).triangulate()
    if pose.type == "plane":
        return pv.Plane(direction=tuple(pose.normal), i_size=2 * PLANE_HALF,
                        j_size=2 * PLANE_HALF)
    return None


class Objects:
    """Translucent collision objects, one actor per object, re-meshed only when a shape
    changes and otherwise just moved."""

    def __init__(self, pv, plotter):
        self.pv, self.plotter = pv, plotter
        self.actors: list = []
        self.shapes: list = []

    def update(self, poses) -> None:
        poses = tuple(poses or ())
        while len(self.actors) > len(poses):
            self.plotter.remove_actor(self.actors.pop(), render=False)
            self.shapes.pop()
        for k, pose in enumerate(poses):
            shape = (pose.type, float(pose.radius), tuple(map(float, pose.size)),
                     tuple(map(float, pose.normal)))
            if k == len(self.actors):
                mesh = _object_mesh(self.pv, pose) or self.pv.PolyData()
                actor = self.plotter.add_mesh(mesh, color=OBJECT_COLOR, opacity=OBJECT_OPACITY,
                                              smooth_shading=pose.type != "box",
                                              specular=0.3, reset_camera=False)
                actor.prop.backface_culling = False
                self.actors.append(actor)
                self.shapes.append(shape)
            elif shape != self.shapes[k]:
                mesh = _object_mesh(self.pv, pose) or self.pv.PolyData()
                self.actors[k].mapper.dataset.copy_from(mesh)
                self.shapes[k] = shape
            centre = np.asarray(pose.center, dtype=np.float64)
            if np.all(np.isfinite(centre)):
                self.actors[k].SetPosition(*centre)
