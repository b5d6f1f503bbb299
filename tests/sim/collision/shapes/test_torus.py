"""The torus: its compiled distance and normal against the analytic ones, its checks, and a
sheet on its tube that friction holds and that slides off without it."""

import numpy as np
import pytest

from cloth_tui.scene import SceneError, SceneObject
from cloth_tui.scene_files import loads
from cloth_tui.sim.collision import colliders
from cloth_tui.sim.model import build_model
from cloth_tui.sim.run.runner import Simulation
from cloth_tui.sim.collision.shapes import torus

from ...helpers import run, scene

CENTRE = np.array([0.1, -0.2, 0.05])
BIG, SMALL = 0.3, 0.1


def ring(axis, m=None):
    m = m or build_model(scene().cloth, scene().behavior)
    obj = SceneObject(type="torus", center=list(CENTRE), axis=list(axis), major_radius=BIG,
                      minor_radius=SMALL)
    return colliders.object_collider(m, obj, friction=0.5, thickness=0.005)


def turned_to_z(axis) -> np.ndarray:
    """The rotation taking `axis` onto +z (Rodrigues), to measure in the torus's own frame."""
    a = np.asarray(axis, float) / np.linalg.norm(axis)
    v, c = np.cross(a, [0.0, 0.0, 1.0]), a[2]
    k = np.array([[0, -v[2], v[1]], [v[2], 0, -v[0]], [-v[1], v[0], 0]])
    return np.eye(3) + k + k @ k / (1.0 + c)


def analytic(q, axis):
    """The textbook torus about z, √((√(x² + y²) − R)² + z²) − r, in the torus's frame."""
    x, y, z = ((q - CENTRE) @ turned_to_z(axis).T).T
    return np.hypot(np.hypot(x, y) - BIG, z) - SMALL


@pytest.mark.parametrize("axis", [(0.0, 1.0, 0.0), (1.0, 0.3, -0.5)])
def test_distance_and_normal_are_the_analytic_ones_at_random_points(axis):
    rng = np.random.default_rng(11)
    q = CENTRE + rng.uniform(-0.6, 0.6, (4000, 3))
    c = ring(axis)
    np.testing.assert_allclose(c.signed_distance(q), analytic(q, axis), atol=1e-12)
    h = 1e-6
    grad = np.stack([(analytic(q + h * e, axis) - analytic(q - h * e, axis)) / (2 * h)
                     for e in np.eye(3)], axis=1)
    x = q.copy()
    depth, normal = np.zeros(len(q)), np.zeros((len(q), 3))
    colliders.collide_shape(x, np.ones(len(q)), np.ones(len(q)), c.shape.code, c.params,
                            c.grid, c.gradient, 10.0, depth, normal)  # every point touches
    np.testing.assert_allclose(normal, grad, atol=1e-5)
    # a point within the skin goes out along its normal to the skin's depth (a ray from the
    # tube's centre circle, which keeps that circle point the nearest); the rest stay
    skin = 0.02
    x = q.copy()
    colliders.collide_shape(x, np.ones(len(q)), np.ones(len(q)), c.shape.code, c.params,
                            c.grid, c.gradient, skin, depth, normal)
    touched = analytic(q, axis) < skin
    assert touched.sum() > 100
    np.testing.assert_allclose(analytic(x[touched], axis), skin, atol=1e-9)
    np.testing.assert_array_equal(x[~touched], q[~touched])


def test_on_the_axis_and_on_the_tube_s_centre_circle():
    c = ring((0.0, 1.0, 0.0))
    on_circle = CENTRE + [BIG, 0.0, 0.0]
    d = c.signed_distance(np.array([CENTRE, CENTRE + [0.0, 0.4, 0.0], on_circle]))
    np.testing.assert_allclose(d, [BIG - SMALL, np.hypot(BIG, 0.4) - SMALL, -SMALL])
    x = on_circle[None, :].copy()
    depth, normal = np.zeros(1), np.zeros((1, 3))
    colliders.collide_shape(x, np.ones(1), np.ones(1), c.shape.code, c.params, c.grid,
                            c.gradient, 0.0, depth, normal)
    np.testing.assert_allclose(x[0], CENTRE + [BIG + SMALL, 0.0, 0.0], atol=1e-12)


def test_the_drawn_surface_is_the_torus():
    params = {"axis": (0.0, 0.6, 0.8), "major_radius": BIG, "minor_radius": SMALL}
    points, triangles = torus.surface(params)
    np.testing.assert_allclose(analytic(points + CENTRE, params["axis"]), 0.0, atol=1e-12)
    assert triangles.min() == 0 and triangles.max() == len(points) - 1
    # closed: every edge is shared by exactly two triangles
    edges = np.sort(np.concatenate([triangles[:, [0, 1]], triangles[:, [1, 2]],
                                    triangles[:, [2, 0]]]), axis=1)
    assert (np.unique(edges, axis=0, return_counts=True)[1] == 2).all()


@pytest.mark.parametrize("keys, message", [
    ("major_radius = 0.1\nminor_radius = 0.1", "minor_radius 0.1 m must be less than its "
                                               "major_radius 0.1 m"),
    ("minor_radius = 0.0", "minor_radius"),
    ("major_radius = -1.0", "major_radius"),
    ("axis = [0.0, 0.0, 0.0]", "axis"),
])
def test_a_torus_that_is_not_one_is_a_one_line_error(keys, message):
    with pytest.raises(SceneError, match=message) as e:
        loads(f'[[objects]]\ntype = "torus"\n{keys}\n')
    assert "\n" not in str(e.value)


def settle_on_the_tube(friction: float):
    """A small free sheet let go just outside the top of a ring's tube (20° down its outer
    side), with the object's own friction."""
    s = scene(cloth__resolution=10, cloth__size=0.16, cloth__pinned="none",
              cloth__height=0.25, scene__floor=False, behavior__substeps=8)
    s.objects = [SceneObject(type="torus", center=[-0.45, 0.0, 0.0], axis=[0.0, 1.0, 0.0],
                             major_radius=0.4, minor_radius=0.15, friction=friction)]
    return run(Simulation(s), 120)


def test_friction_holds_a_sheet_on_the_tube_and_without_it_the_sheet_slides_off():
    held = settle_on_the_tube(1.0)
    st = held.stats()
    assert st.finite and st.penetration <= held.scene.scene.thickness + 1e-3
    x = held.state.x
    assert abs(x[:, 0].mean()) < 0.01 and x[:, 1].min() > 0.05  # still where it landed
    assert st.max_speed < 0.01
    c = held.step.colliders[0]
    assert c.name == "collide_torus" and c.signed_distance(x).min() > 0.0
    slid = settle_on_the_tube(0.0)
    assert slid.stats().finite and slid.state.x[:, 1].max() < -0.5  # fell off it
