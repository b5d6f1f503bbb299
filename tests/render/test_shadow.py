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
    index, tri = coarse_grid(100, side=33)
    m = int(round(np.sqrt(len(index))))
    assert m == 33 and len(tri) == 2 * 32 * 32
    assert {0, 99, 99 * 100, 100 * 100 - 1} <= set(index.tolist())
    assert tri.min() == 0 and tri.max() == len(index) - 1
    small, small_tri = coarse_grid(5)
    np.testing.assert_array_equal(small, np.arange(25))  # a small sheet whole
