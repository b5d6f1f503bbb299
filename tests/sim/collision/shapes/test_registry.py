"""Every registered shape through every consumer: a scene file's [[objects]] table, the
compiled distance, the render mesh, a USD bake and reading it back; and an unknown type
refused by each of them."""

from pathlib import Path

import numpy as np
import pytest

from cloth_tui.scene import OBJECT_TYPES, SceneError, SceneObject
from cloth_tui.scene_files import loads
from cloth_tui.sim.collision import colliders
from cloth_tui.sim.model import build_model
from cloth_tui.sim.protocols import ObjectPose
from cloth_tui.sim.collision.shapes import SHAPES, UnknownShapeError, shape_of

TORUS_PLY = Path(__file__).parents[4] / "assets" / "meshes" / "torus.ply"
CENTRE = (0.1, -0.2, 0.05)

# Keys of one object of each registered shape, as a scene file writes them, and a point
# inside it relative to its centre. A shape registered without an entry here fails
# test_every_shape_has_an_example.
EXAMPLES = {
    "sphere": ('radius = 0.2', (0.0, 0.0, 0.0)),
    "box": ('size = [0.3, 0.2, 0.4]', (0.0, 0.0, 0.0)),
    "plane": ('normal = [0.0, 1.0, 0.3]', (0.0, -0.1, 0.0)),
    "capsule": ('radius = 0.1\nlength = 0.3\naxis = [0.0, 0.0, 1.0]', (0.0, 0.0, 0.0)),
    # the file's torus: ring 0.25 m, tube 0.08 m, about z
    "mesh": (f'path = "{TORUS_PLY}"', (0.25, 0.0, 0.0)),
    "cylinder": ('radius = 0.1\nheight = 0.3\naxis = [0.0, 1.0, 1.0]', (0.0, 0.05, 0.05)),
    # inside the tube, on its centre circle
    "torus": ('major_radius = 0.2\nminor_radius = 0.05\naxis = [0.0, 1.0, 1.0]', (0.2, 0.0, 0.0)),
}
# How far a render mesh's vertices may lie from the surface the kernel collides with, m:
# analytic shapes put their vertices on it; a mesh's grid blends its samples (a cell is
# half the particle spacing: 1.3 cm at resolution 40).
ON_SURFACE = {"mesh": 0.01}


def test_every_shape_has_an_example():
    assert set(EXAMPLES) == set(SHAPES) == set(OBJECT_TYPES)


def parsed(name: str):
    text = (f'[cloth]\nresolution = 40\n\n[[objects]]\ntype = "{name}"\n'
            f'center = [{", ".join(map(str, CENTRE))}]\n{EXAMPLES[name][0]}\n')
    return loads(text)


@pytest.fixture(scope="module", params=sorted(EXAMPLES))
def collider(request):
    scene = parsed(request.param)
    assert scene.objects[0].type == request.param
    model = build_model(scene.cloth, scene.behavior)
    (c,) = [c for c in colliders.build_colliders(scene, model) if c.name != "collide_floor"]
    return c


def test_the_kernel_measures_inside_outside_and_far(collider):
    far = np.array([[CENTRE[0], CENTRE[1] + 5.0, CENTRE[2]]])
    d_far = collider.signed_distance(far)[0]
    assert np.isfinite(d_far) and d_far > 1.0
    offset = np.asarray(EXAMPLES[collider.shape.name][1])
    d_in = collider.signed_distance((np.asarray(CENTRE) + offset)[None, :])[0]
    if collider.shape.sided:  # no side known yet: each point is on its own
        normal = np.asarray(collider.parameters["normal"])
        assert d_in == pytest.approx(abs(offset @ normal))
    else:
        assert d_in < -0.01


def test_the_render_mesh_lies_on_the_surface_the_kernel_collides_with(collider):
    pv = pytest.importorskip("pyvista")
    pose = collider.pose(0.0)
    assert pose.type == collider.shape.name and pose.center == pytest.approx(CENTRE)
    mesh = shape_of(pose.type).render_mesh(pv, pose.parameters)
    points = np.asarray(mesh.points, dtype=np.float64)
    assert mesh.n_cells > 0 and len(points) > 3
    d = collider.signed_distance(points + np.asarray(CENTRE))
    assert np.abs(d).max() < ON_SURFACE.get(pose.type, 1e-3)


def test_a_bake_reads_back_the_pose(collider, tmp_path):
    pytest.importorskip("pxr")
    from cloth_tui.io.frames import BakedFrame
    from cloth_tui.io.usd_bake import UsdBakeWriter
    from cloth_tui.io.usd_read import UsdBake

    scene = parsed(collider.shape.name)
    model = build_model(scene.cloth, scene.behavior)
    path = tmp_path / "b.usda"
    writer = UsdBakeWriter(path, scene, model)
    pose = collider.pose(0.0)
    writer.write(BakedFrame(1, 0.0, model.rest_positions.copy(), (pose,)))
    writer.close()
    (back,) = UsdBake(path).objects(1)
    assert back.type == pose.type and back.center == pytest.approx(pose.center)
    assert back.parameters.keys() == pose.parameters.keys()
    for name, value in pose.parameters.items():
        if name == "surface":  # float32 points, the same triangles
            np.testing.assert_allclose(back.parameters[name].vertices, value.vertices,
                                       atol=1e-6)
            np.testing.assert_array_equal(back.parameters[name].faces, value.faces)
        else:
            assert back.parameters[name] == pytest.approx(value)


def test_an_unknown_type_is_refused_everywhere(tmp_path):
    with pytest.raises(SceneError, match="objects\\[0\\].type = 'teapot'"):
        loads('[[objects]]\ntype = "teapot"\n')
    with pytest.raises(UnknownShapeError, match="teapot"):
        shape_of("teapot")
    model = build_model(parsed("sphere").cloth, parsed("sphere").behavior)
    with pytest.raises(UnknownShapeError):
        colliders.object_collider(model, SceneObject(type="teapot"), friction=0.5,
                                  thickness=0.005)
    teapot = ObjectPose("teapot", {}, (0.0, 0.0, 0.0))
    pv = pytest.importorskip("pyvista")
    from cloth_tui.render.props import Objects

    class Plotter:
        def add_mesh(self, *a, **k):
            raise AssertionError("an unknown type reached the plotter")
    with pytest.raises(UnknownShapeError):
        Objects(pv, Plotter()).update((teapot,))
    pytest.importorskip("pxr")
    from cloth_tui.io.frames import BakedFrame
    from cloth_tui.io.usd_bake import UsdBakeWriter
    scene = parsed("sphere")
    writer = UsdBakeWriter(tmp_path / "t.usda", scene, model)
    with pytest.raises(UnknownShapeError):
        writer.write(BakedFrame(1, 0.0, model.rest_positions.copy(), (teapot,)))
