import numpy as np

from cloth_tui.sim.model import build_model
from cloth_tui.scene import Scene
from cloth_tui.sim.collision.surface import (grid_cell_triangles, grid_uv, thinned_rows,
                                             vertex_normals)


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


def test_thinned_triangles_of_a_rectangle_keep_the_models_winding():
    # 3 rows of 7 particles: thinning rows and columns alike keeps every face's normal up,
    # as the model's own triangles (the sub-grid of all rows and columns) have it.
    s = Scene().with_values({"cloth.resolution": [7, 3], "cloth.size": [3.0, 1.0]})
    model = build_model(s.cloth, s.behavior)
    full = grid_cell_triangles(7, np.arange(3), np.arange(7))
    np.testing.assert_array_equal(full, model.triangles)
    thin = grid_cell_triangles(7, thinned_rows(3, 2), thinned_rows(7, 3))
    assert len(thin) == 2 * 1 * 2  # rows 0, 2 and columns 0, 3, 6: 1 × 2 cells
    assert set(np.unique(thin)) == {0, 3, 6, 14, 17, 20}
    x = model.rest_positions
    face = np.cross(x[thin[:, 1]] - x[thin[:, 0]], x[thin[:, 2]] - x[thin[:, 0]])
    model_face = np.cross(x[full[:, 1]] - x[full[:, 0]], x[full[:, 2]] - x[full[:, 0]])
    assert np.sign(face[:, 1]).tolist() == [np.sign(model_face[0, 1])] * len(thin)


def test_a_square_shows_the_whole_image_once():
    uv = grid_uv(5, 5, 1.0, 1.0).reshape(5, 5, 2)
    np.testing.assert_array_equal(uv[0, :, 0], np.linspace(0.0, 1.0, 5))
    np.testing.assert_array_equal(uv[:, 0, 1], 1.0 - np.linspace(0.0, 1.0, 5))


def test_a_rectangles_texture_keeps_its_proportions():
    # 2 m × 1 m: the image spans the width once, the length shows its middle half, so one
    # texel covers the same distance along x and z (the image is not squashed).
    nx, nz, width, length = 21, 6, 2.0, 1.0
    uv = grid_uv(nx, nz, width, length).reshape(nz, nx, 2)
    np.testing.assert_allclose(uv[0, [0, -1], 0], [0.0, 1.0])
    np.testing.assert_allclose(uv[[0, -1], 0, 1], [0.75, 0.25])
    du_per_m = (uv[0, -1, 0] - uv[0, 0, 0]) / width
    dv_per_m = (uv[0, 0, 1] - uv[-1, 0, 1]) / length
    assert du_per_m == np.float64(dv_per_m)
    tall = grid_uv(nz, nx, length, width).reshape(nx, nz, 2)  # the same sheet turned
    np.testing.assert_allclose(tall[0, [0, -1], 0], [0.25, 0.75])
    np.testing.assert_allclose(tall[[0, -1], 0, 1], [1.0, 0.0])
