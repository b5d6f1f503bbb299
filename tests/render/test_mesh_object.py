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
    ball = surface(pv.Sphere(radius=SPHERE.parameters["radius"], theta_resolution=40, phi_resolution=24),
                   "ball")
    as_mesh = renderer.render(draped(scene, sag=0.05, objects=(ObjectPose(
        "mesh", {"surface": ball}, SPHERE.center),))).copy()
    analytic = renderer.render(draped(scene, sag=0.05, objects=(SPHERE,))).copy()
    assert np.abs(as_mesh.astype(int) - analytic).mean() < \
        0.2 * np.abs(with_torus.astype(int) - analytic).mean()
