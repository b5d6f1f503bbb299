import numpy as np

from cloth_tui.sim.model import build_model
from cloth_tui.scene import Scene
from cloth_tui.sim.surface import vertex_normals


def numpy_normals(points, triangles):
    """The plain NumPy formula the kernel replaced: the reference."""
    a, b, c = (points[triangles[:, k]] for k in range(3))
    face = np.cross(b - a, c - a)
    out = np.zeros_like(points)
    for k in range(3):
        np.add.at(out, triangles[:, k], face)
    length = np.linalg.norm(out, axis=1, keepdims=True)
    return np.where(length < 1e-20, [0.0, 1.0, 0.0], out / np.maximum(length, 1e-300))


def crumpled(n=9, seed=3):
    model = build_model(Scene().with_value("cloth.resolution", n).cloth, Scene().behavior)
    x = np.array(model.rest_positions, dtype=np.float64)
    x += np.random.default_rng(seed).normal(scale=0.05, size=x.shape)
    return x, np.asarray(model.triangles, dtype=np.int64)


def test_kernel_normals_match_the_numpy_formula_on_a_crumpled_sheet():
    x, tri = crumpled()
    np.testing.assert_allclose(vertex_normals(x, tri), numpy_normals(x, tri), atol=1e-12)


def test_normals_are_written_into_the_given_array_in_place():
    x, tri = crumpled()
    out = np.zeros((len(x), 3), np.float32)
    result = vertex_normals(x, tri, out=out)
    assert result is out
    np.testing.assert_allclose(out, numpy_normals(x, tri), atol=1e-6)


def test_a_vertex_with_only_zero_area_triangles_points_up():
    x, tri = crumpled(n=4)
    x[:] = 0.0  # every triangle collapsed to a point
    np.testing.assert_array_equal(vertex_normals(x, tri), np.tile([0.0, 1.0, 0.0], (len(x), 1)))
