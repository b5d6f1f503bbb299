"""A mesh collider is drawn from its own triangles, where its pose puts it."""

import numpy as np
import pyvista as pv

from cloth_tui.meshes import MeshSurface
from cloth_tui.sim.protocols import ObjectPose

from .helpers import SPHERE, draped, scene_with


def surface(mesh, key: str) -> MeshSurface:
    return MeshSurface(key, np.asarray(mesh.points, dtype=np.float64),
                       np.asarray(mesh.regular_faces, dtype=np.int64))


def test_a_mesh_object_is_drawn_from_its_triangles(renderer):
    # (render returns the renderer's own buffer: each picture is copied before the next)
    scene = scene_with(wireframe=False)
    renderer.update_scene(scene)
    renderer.reset_camera()
    without = renderer.render(draped(scene, sag=0.05)).copy()
    torus = surface(pv.ParametricTorus(ringradius=0.3, crosssectionradius=0.1).rotate_x(90)
                    .triangulate(), "torus")
    pose = ObjectPose("mesh", {"surface": torus}, (0.0, -0.25, 0.0))
    with_torus = renderer.render(draped(scene, sag=0.05, objects=(pose,))).copy()
    assert np.abs(with_torus.astype(int) - without).mean() > 0.3
    # the same place with a sphere's triangles looks like the analytic sphere, not the torus
    ball = surface(pv.Sphere(radius=SPHERE.parameters["radius"], theta_resolution=40,
                             phi_resolution=24),
                   "ball")
    as_mesh = renderer.render(draped(scene, sag=0.05, objects=(ObjectPose(
        "mesh", {"surface": ball}, SPHERE.center),))).copy()
    analytic = renderer.render(draped(scene, sag=0.05, objects=(SPHERE,))).copy()
    assert np.abs(as_mesh.astype(int) - analytic).mean() < \
        0.2 * np.abs(with_torus.astype(int) - analytic).mean()


def test_a_torus_is_drawn_as_a_torus_where_its_pose_puts_it(renderer):
    scene = scene_with(wireframe=False)
    renderer.update_scene(scene)
    renderer.reset_camera()
    centre = (0.0, -0.25, 0.0)
    without = renderer.render(draped(scene, sag=0.05)).copy()
    ring = ObjectPose("torus", {"axis": (0.0, 1.0, 0.0), "major_radius": 0.3,
                                "minor_radius": 0.1}, centre)
    drawn = renderer.render(draped(scene, sag=0.05, objects=(ring,))).copy()
    assert np.abs(drawn.astype(int) - without).mean() > 0.3
    # PyVista's own torus (made about z, turned onto y) as a mesh, there: the same picture
    reference = surface(pv.ParametricTorus(ringradius=0.3, crosssectionradius=0.1,
                                           u_res=96, v_res=48).rotate_x(90).triangulate(),
                        "pyvista torus")
    as_mesh = renderer.render(draped(scene, sag=0.05, objects=(ObjectPose(
        "mesh", {"surface": reference}, centre),))).copy()
    # and a torus a little off, to show how much a wrong place or size changes
    moved = ObjectPose("torus", dict(ring.parameters, minor_radius=0.07), centre)
    off = renderer.render(draped(scene, sag=0.05, objects=(moved,))).copy()
    assert np.abs(as_mesh.astype(int) - drawn).mean() < \
        0.3 * np.abs(off.astype(int) - drawn).mean()
