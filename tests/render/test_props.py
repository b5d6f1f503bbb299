"""The still parts of the picture: the ground's mesh is as fine as its fog needs and no finer."""

import numpy as np

from cloth_tui.render.geometry import fog_factor
from cloth_tui.render.props import (FOG_FAR, FOG_NEAR, FOG_TOLERANCE, fog_disc,
                                    fog_ring_radii)
from cloth_tui.render.vtk_setup import pyvista_quiet


def test_the_grounds_rings_draw_its_fog_within_tolerance_and_end_where_fog_is_whole():
    radii = fog_ring_radii()
    assert radii[0] == FOG_NEAR and radii[-1] == FOG_FAR and np.all(np.diff(radii) > 0)
    r = np.linspace(0.0, FOG_FAR, 5001)
    drawn = np.interp(r, np.r_[0.0, radii], fog_factor(np.r_[0.0, radii], FOG_NEAR, FOG_FAR))
    assert np.abs(drawn - fog_factor(r, FOG_NEAR, FOG_FAR)).max() <= 1.01 * FOG_TOLERANCE
    assert len(radii) < 12  # dense only where the curve bends
    assert fog_factor(np.array([FOG_FAR]), FOG_NEAR, FOG_FAR)[0] == 1.0  # beyond: background


def test_the_ground_disc_faces_up_and_reaches_the_fogs_end_with_few_triangles():
    disc = fog_disc(pyvista_quiet())
    points = np.asarray(disc.points)
    assert np.allclose(points[:, 1], 0.0)
    assert np.isclose(np.hypot(points[:, 0], points[:, 2]).max(), FOG_FAR)
    assert disc.n_cells < 1000  # 20 even rings to 14 m were 1,872
    faces = disc.faces.reshape(-1, 4)[:, 1:]
    a, b, c = (points[faces[:, k]] for k in range(3))
    assert (np.cross(b - a, c - a)[:, 1] > 0).all()  # every triangle faces up
