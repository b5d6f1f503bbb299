import numpy as np

from cloth_tui.render.geometry import LIGHT_DIR
from cloth_tui.render.shadow import LIFT, coarse_grid, project_to_floor


def test_points_are_moved_along_the_sun_onto_the_floor():
    points = np.array([[0.0, 1.0, 0.0], [0.3, -0.2, 0.1], [0.0, -0.5, 0.0]])
    out = project_to_floor(points, -0.5, np.empty((3, 3)))
    np.testing.assert_allclose(out[:, 1], -0.5 + LIFT)
    for p, q in zip(points, out):
        along = p - q
        along[1] = p[1] - (-0.5)  # the drop itself, without the lift
        np.testing.assert_allclose(np.cross(along, LIGHT_DIR), 0.0, atol=1e-12)
    np.testing.assert_allclose(out[2, [0, 2]], [0.0, 0.0])  # on the floor: its own shadow


def test_the_coarse_copy_keeps_the_corners_and_covers_the_sheet():
    index, tri = coarse_grid(100, 100, side=33)
    m = int(round(np.sqrt(len(index))))
    assert m == 33 and len(tri) == 2 * 32 * 32
    assert {0, 99, 99 * 100, 100 * 100 - 1} <= set(index.tolist())
    assert tri.min() == 0 and tri.max() == len(index) - 1
    small, small_tri = coarse_grid(5, 5)
    np.testing.assert_array_equal(small, np.arange(25))  # a small sheet whole


def test_the_coarse_copy_of_a_strip_thins_each_side_by_itself():
    # 120 columns, 6 rows: the columns thinned to 33, the 6 rows all kept.
    nx, nz = 120, 6
    index, tri = coarse_grid(nx, nz, side=33)
    assert len(index) == 33 * 6 and len(tri) == 2 * 32 * 5
    rows, cols = np.divmod(index, nx)
    assert sorted(set(rows.tolist())) == list(range(6))
    assert {0, nx - 1} <= set(cols.tolist()) and len(set(cols.tolist())) == 33
    assert {0, nx - 1, nx * (nz - 1), nx * nz - 1} <= set(index.tolist())
    # the copy's triangles cover its cells in the model's winding: a flat strip's face
    # normals all point one way
    x = np.stack([cols * 1.0, np.zeros(len(index)), rows * 1.0], axis=1)
    y = np.cross(x[tri[:, 1]] - x[tri[:, 0]], x[tri[:, 2]] - x[tri[:, 0]])[:, 1]
    assert (np.sign(y) == np.sign(y[0])).all() and y[0] != 0
