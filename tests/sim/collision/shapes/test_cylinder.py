"""The capped cylinder: its compiled distance and normal against the analytic ones, and a
sheet dropped on a post settles on it without passing through."""

import numpy as np
import pytest

from cloth_tui.scene import SceneObject
from cloth_tui.sim.collision import colliders
from cloth_tui.sim.model import build_model
from cloth_tui.sim.run.runner import Simulation

from ...helpers import run, scene

CENTRE = np.array([0.1, -0.2, 0.05])
RADIUS, HEIGHT = 0.15, 0.4


def cylinder(axis, m=None):
    m = m or build_model(scene().cloth, scene().behavior)
    obj = SceneObject(type="cylinder", center=list(CENTRE), radius=RADIUS, height=HEIGHT,
                      axis=list(axis))
    return colliders.object_collider(m, obj, friction=0.5, thickness=0.005)


def analytic(q, axis):
    """The capped cylinder's exact signed distance (Quílez's formula) at points q."""
    a = np.asarray(axis, float) / np.linalg.norm(axis)
    rel = q - CENTRE
    t = rel @ a
    rho = np.linalg.norm(rel - t[:, None] * a, axis=1)
    dr, dh = rho - RADIUS, np.abs(t) - HEIGHT / 2
    outside = np.hypot(np.maximum(dr, 0.0), np.maximum(dh, 0.0))
    return np.minimum(np.maximum(dr, dh), 0.0) + outside


@pytest.mark.parametrize("axis", [(0.0, 1.0, 0.0), (1.0, 0.3, -0.5)])
def test_distance_and_normal_are_the_analytic_ones_at_random_points(axis):
    rng = np.random.default_rng(7)
    q = CENTRE + rng.uniform(-0.5, 0.5, (4000, 3))
    c = cylinder(axis)
    np.testing.assert_allclose(c.signed_distance(q), analytic(q, axis), atol=1e-12)
    # the normal is the distance's gradient (central differences, away from the rims and
    # the inside's medial surfaces where it jumps)
    h = 1e-6
    grad = np.stack([(analytic(q + h * e, axis) - analytic(q - h * e, axis)) / (2 * h)
                     for e in np.eye(3)], axis=1)
    smooth = np.abs(np.linalg.norm(grad, axis=1) - 1.0) < 1e-4
    assert smooth.sum() > 3000
    x = q.copy()
    depth, normal = np.zeros(len(q)), np.zeros((len(q), 3))
    colliders.collide_shape(x, np.ones(len(q)), np.ones(len(q)), c.shape.code, c.params,
                            c.grid, c.gradient, 10.0, depth, normal)  # every point touches
    np.testing.assert_allclose(normal[smooth], grad[smooth], atol=1e-5)
    # each point went out along its normal to 10 m from the surface
    np.testing.assert_allclose(analytic(x, axis), 10.0, atol=1e-9)


def test_a_point_on_the_axis_leaves_across_it_or_through_the_nearer_end():
    c = cylinder((0.0, 1.0, 0.0))
    d = c.signed_distance(np.array([CENTRE, CENTRE + [0.0, 0.15, 0.0]]))
    np.testing.assert_allclose(d, [-RADIUS, -0.05])


def test_a_sheet_dropped_on_a_post_rests_on_its_top_and_hangs_around_it():
    s = scene(cloth__resolution=16, cloth__pinned="none", cloth__height=0.15,
              scene__floor=False, behavior__substeps=8)
    s.objects = [SceneObject(type="cylinder", center=[0.0, -0.1, 0.0], radius=0.15,
                             height=0.4, axis=[0.0, 1.0, 0.0])]
    sim = run(Simulation(s), 90)
    st = sim.stats()
    assert st.finite and st.penetration <= s.scene.thickness + 1e-3
    x = sim.state.x
    top = 0.1 + s.scene.thickness
    on_top = np.hypot(x[:, 0], x[:, 2]) < 0.1
    # held up by the cap (the bending constraints over its rim lift the middle a little)
    assert on_top.any()
    assert (x[on_top, 1] > top - 1e-3).all() and (x[on_top, 1] < top + 0.03).all()
    assert x[:, 1].min() < top - 0.15  # the rest hangs down around the post
    c = sim.step.colliders[0]
    assert c.name == "collide_cylinder" and c.signed_distance(x).min() > 0.0
