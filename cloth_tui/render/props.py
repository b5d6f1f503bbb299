"""The still parts of the picture: ground, corner poles and collision objects. Each is built
once and changed in place (points, position, colours), so a long session never piles up
actors. Runs only on the render thread, like everything that touches VTK."""

from __future__ import annotations

import numpy as np

from .geometry import AMBIENT, fog_factor, hex_rgb

GROUND_RADIUS = 14.0  # m: far enough that fog hides the edge
FOG_NEAR, FOG_FAR = 2.0, 11.0  # m from the centre: the original's fog, scaled to its camera
POLE_COLOR = "#c8c8c8"
OBJECT_COLOR = "#e8e3d8"
OBJECT_OPACITY = 0.55
PLANE_HALF = 0.9  # m: shown extent of an (infinite) collision plane, about the sheet's
PLANE_OPACITY = 0.35  # a plane spans the view: fainter, so the cloth stays the subject


class Ground:
    """A lit disc at the floor height, optionally textured (tiled), under a translucent fog
    disc whose opacity grows with distance from the centre: the ground fades into the
    background colour and its edge vanishes, as with the original's linear fog. (A separate
    fog layer, because VTK drops vertex colours on a textured mesh.)"""

    def __init__(self, pv, plotter):
        self.pv = pv
        disc = pv.Disc(inner=0.0, outer=GROUND_RADIUS, normal=(0, 1, 0), r_res=40, c_res=96)
        self.mesh = disc.triangulate()
        pts = np.asarray(self.mesh.points)
        self.base_xz = pts[:, [0, 2]].copy()  # for a 1 m sheet; scaled with the sheet
        self.mesh.active_texture_coordinates = pts[:, [0, 2]] / 0.5  # one tile per 0.5 m
        self.actor = plotter.add_mesh(self.mesh, reset_camera=False, ambient=1.0,
                                      diffuse=0.75, specular=0.0)
        # Only the ring where fog is non-zero: translucent pixels cost most in software GL.
        self.fog = pv.Disc(inner=FOG_NEAR, outer=GROUND_RADIUS, normal=(0, 1, 0), r_res=30,
                           c_res=96).triangulate()
        fog_pts = np.asarray(self.fog.points)
        self.fog_base_xz = fog_pts[:, [0, 2]].copy()
        self.fog_alpha = fog_factor(np.hypot(fog_pts[:, 0], fog_pts[:, 2]), FOG_NEAR, FOG_FAR)
        self.fog.point_data["rgba"] = np.zeros((len(fog_pts), 4), np.uint8)
        self.fog_actor = plotter.add_mesh(self.fog, scalars="rgba", rgba=True, lighting=False,
                                          show_scalar_bar=False, reset_camera=False)

    def update(self, scene, texture_image) -> None:
        s, a = scene.scene, scene.appearance
        for actor in (self.actor, self.fog_actor):
            actor.SetVisibility(bool(s.floor))
        scale = max(1.0, scene.cloth.size)  # a big sheet gets a wider ground and fog
        self.mesh.points[:, [0, 2]] = self.base_xz * scale
        self.fog.points[:, [0, 2]] = self.fog_base_xz * scale
        self.mesh.points[:, 1] = s.floor_height
        self.fog.points[:, 1] = s.floor_height + 0.002  # just above, never through the cloth
        for mesh in (self.mesh, self.fog):
            mesh.GetPoints().Modified()
            mesh.Modified()
        if texture_image is not None:
            tex = self.pv.Texture(texture_image)
            tex.repeat = True
            tex.mipmap = True
            tex.interpolate = True
            self.actor.texture = tex
            base = np.ones(3)  # a texture carries its own colour
        else:
            self.actor.texture = None
            base = hex_rgb(a.ground_color)
        prop = self.actor.prop
        prop.color = tuple(base)
        prop.ambient_color = tuple(np.clip(AMBIENT * base + hex_rgb(a.ground_emissive), 0, 1))
        rgba = self.fog.point_data["rgba"]
        rgba[:, :3] = (hex_rgb(a.fog_color) * 255 + 0.5).astype(np.uint8)
        rgba[:, 3] = (self.fog_alpha * 255 + 0.5).astype(np.uint8)
        self.fog.point_data["rgba"].VTKObject.Modified()
        self.fog.Modified()


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
                opacity = PLANE_OPACITY if pose.type == "plane" else OBJECT_OPACITY
                actor = self.plotter.add_mesh(mesh, color=OBJECT_COLOR, opacity=opacity,
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
