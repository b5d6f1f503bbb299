"""Colliders: shapes, the original's friction rule, moving objects, two-sided planes."""

import math

import numpy as np
import pytest

from cloth_tui.scene import SceneObject
from cloth_tui.sim import colliders
from cloth_tui.sim.model import build_model
from cloth_tui.sim.runner import Simulation
from .helpers import run, scene


def one_particle_model():
    s = scene(cloth__resolution=2, cloth__pinned="none")
    return build_model(s.cloth, s.behavior)


# -- kernels on single particles ------------------------------------------------------------
def four(p):
    return np.tile(np.asarray(p, float), (4, 1))


def collide(kind, p, p_prev, friction=0.0, thickness=0.01, **shape):
    """Run one collider on four copies of a particle; return the new position."""
    m = one_particle_model()
    c = colliders.ObjectCollider(m, kind, shape.pop("center", (0.0, 0.0, 0.0)),
                                 friction=friction, thickness=thickness, **shape)

    class S:
        x = np.tile(np.asarray(p, float), (4, 1))
        x_prev = np.tile(np.asarray(p_prev, float), (4, 1))
        t = 0.0
    c.apply(S, 0.01)
    return S.x[0], c


def test_sphere_pushes_out_to_surface_plus_thickness():
    x, c = collide("sphere", (0.0, 0.2, 0.0), (0.0, 0.3, 0.0), radius=0.25)
    np.testing.assert_allclose(x, [0.0, 0.26, 0.0])
    assert c.penetration(four(x)) == 0.0
    assert c.penetration(four([0.0, 0.2, 0.0])) == pytest.approx(0.05)


def test_box_leaves_through_the_nearest_face_and_corners_round():
    x, c = collide("box", (0.1, 0.05, 0.0), (0.1, 0.05, 0.0), size=(0.5, 0.2, 0.5))
    np.testing.assert_allclose(x, [0.1, 0.11, 0.0])  # the top face is nearest
    x, _ = collide("box", (0.253, 0.103, 0.0), (0.4, 0.25, 0.0), size=(0.5, 0.2, 0.5))
    e = 0.01 / math.sqrt(2)  # 3 mm out from the edge in x and y: out along the diagonal
    np.testing.assert_allclose(x, [0.25 + e, 0.1 + e, 0.0])

    x, _ = collide("box", (0.24, 0.0, 0.0), (0.3, 0.0, 0.0), size=(0.5, 0.2, 0.5))
    np.testing.assert_allclose(x, [0.26, 0.0, 0.0])
    assert c.penetration(four([0.0, 0.0, 0.0])) == pytest.approx(0.1)


def test_capsule_pushes_radially_from_its_axis_and_rounds_its_ends():
    x, c = collide("capsule", (0.1, 0.05, 0.0), (0.1, 0.3, 0.0), radius=0.1,
                   length=0.4, axis=(1.0, 0.0, 0.0))
    np.testing.assert_allclose(x, [0.1, 0.11, 0.0])
    x, _ = collide("capsule", (0.25, 0.0, 0.0), (0.4, 0.0, 0.0), radius=0.1,
                   length=0.4, axis=(1.0, 0.0, 0.0))
    np.testing.assert_allclose(x, [0.31, 0.0, 0.0])  # past the end cap: out along the axis
    assert c.penetration(four([0.0, 0.0, 0.0])) == pytest.approx(0.1)


def test_plane_collides_from_both_sides():
    # the particle keeps the side its previous position was on
    above, _ = collide("plane", (0.0, -0.005, 0.0), (0.0, 0.1, 0.0))
    below, c = collide("plane", (0.0, 0.005, 0.0), (0.0, -0.1, 0.0))
    np.testing.assert_allclose(above, [0.0, 0.01, 0.0])
    np.testing.assert_allclose(below, [0.0, -0.01, 0.0])
    assert c.penetration(four([0.0, 0.02, 0.0])) == pytest.approx(0.02)


def test_friction_blends_previous_and_projected_positions():
    # x_prev outside, sliding along x while sinking in: F = 0.5 keeps half the slide
    kw = dict(radius=0.25, center=(0.0, -0.25, 0.0))
    new, prev = (0.05, -0.01, 0.0), (0.0, 0.02, 0.0)
    free, _ = collide("sphere", new, prev, friction=0.0, **kw)
    held, _ = collide("sphere", new, prev, friction=1.0, **kw)
    half, _ = collide("sphere", new, prev, friction=0.5, **kw)
    assert np.linalg.norm(free - [0.0, -0.25, 0.0]) == pytest.approx(0.26)
    np.testing.assert_allclose(held, prev, atol=1e-12)  # held where it was
    np.testing.assert_allclose(half, 0.5 * free + 0.5 * held, atol=1e-12)
    # a moving object carries a held particle along (posFriction = x_prev + displacement)
    m = one_particle_model()
    c = colliders.ObjectCollider(m, "box", (0.0, 0.0, 0.0), size=(0.5, 0.2, 0.5), friction=1.0,
                                 thickness=0.01, moving=True)

    class S:
        x_prev = four([0.0, 0.1 + 0.01, 0.0])  # resting on the top face's skin
        x = x_prev - [0.0, 0.001, 0.0]  # gravity pulled it in a little
        t = 1.0
    c.apply(S, 0.05)
    shift = colliders.orbit_offset(1.05) - colliders.orbit_offset(1.0)
    np.testing.assert_allclose(S.x[0], S.x_prev[0] + shift, atol=1e-12)
    # previous position already inside: no friction, plain projection
    inside, _ = collide("sphere", new, (0.0, -0.1, 0.0), friction=1.0, **kw)
    np.testing.assert_allclose(inside, free)


# -- whole sheets ---------------------------------------------------------------------------
def on_slope(friction):
    # the original's single plane, tilted 20° about x: downhill is +z
    s = scene(cloth__resolution=10, cloth__pinned="none", scene__object="plane",
              scene__floor=False, scene__friction=friction, behavior__substeps=6)
    sim = run(Simulation(s), 60)  # landed
    z0 = sim.state.x[:, 2].mean()
    run(sim, 120)
    return sim, sim.state.x[:, 2].mean() - z0


def test_sheet_stays_on_a_20_degree_slope_with_friction_1_and_slides_with_0():
    held, dz_held = on_slope(1.0)
    slid, dz_slid = on_slope(0.0)
    assert abs(dz_held) < 1e-3
    assert dz_slid > 0.5  # tan 20° > 0: without friction it accelerates downhill
    for sim in (held, slid):
        assert sim.stats()["penetration"] <= sim.scene.scene.thickness + 1e-3


@pytest.mark.parametrize("obj", ["none", "sphere", "box", "plane", "capsule"])
def test_no_particle_sinks_deeper_than_the_skin_after_settling(obj):
    s = scene(cloth__resolution=16, cloth__pinned="none", scene__object=obj,
              behavior__substeps=8)
    sim = run(Simulation(s), 150)
    st = sim.stats()
    assert st["finite"] and st["max_speed"] < 0.5
    assert st["penetration"] <= s.scene.thickness + 1e-3
    expected = {"none": ["collide_floor"]}.get(obj, ["collide_floor", f"collide_{obj}"])
    assert [n for n in st["effects"] if n.startswith("collide")] == expected


def test_moving_sphere_drags_a_draped_sheet():
    def centroid_shift(moving):
        s = scene(cloth__resolution=14, cloth__pinned="none", scene__object="sphere",
                  scene__moving=moving, scene__friction=0.9, scene__floor=False,
                  behavior__substeps=8)
        sim = Simulation(s)
        x0 = sim.state.x.mean(axis=0)
        run(sim, 120)  # 2 s: the sphere has moved ≈ 0.3 m along its circle
        return sim.state.x.mean(axis=0) - x0, sim
    still, _ = centroid_shift(False)
    moved, sim = centroid_shift(True)
    sphere_shift = colliders.orbit_offset(sim.state.t)
    assert np.hypot(still[0], still[2]) < 0.05
    # carried along in the sphere's direction of travel, a good share of its motion
    along = (moved[0] * sphere_shift[0] + moved[2] * sphere_shift[2]) / np.hypot(
        sphere_shift[0], sphere_shift[2])
    assert along > 0.3 * np.hypot(sphere_shift[0], sphere_shift[2])
    assert sim.stats()["penetration"] <= sim.scene.scene.thickness + 1e-3


def test_orbit_pose_and_static_pose():
    m = one_particle_model()
    c = colliders.ObjectCollider(m, "sphere", (0.0, -0.25, 0.0), moving=True)
    assert c.pose(0.0).center == pytest.approx((0.0, -0.25, 0.0))
    half = c.pose(colliders.ORBIT_PERIOD / 2)
    assert half.center == pytest.approx((0.0, -0.25, 2 * colliders.ORBIT_RADIUS))
    assert c.pose(colliders.ORBIT_PERIOD).center == pytest.approx((0.0, -0.25, 0.0), abs=1e-12)
    still = colliders.ObjectCollider(m, "box", (1.0, 2.0, 3.0), size=(0.1, 0.2, 0.3))
    assert still.pose(5.0) == colliders.ObjectPose("box", (1.0, 2.0, 3.0), 0.25,
                                                    (0.1, 0.2, 0.3), (0.0, 1.0, 0.0))


def test_objects_list_builds_multi_object_scenes_in_order():
    s = scene(scene__object="box", scene__friction=0.4)
    s.objects = [SceneObject(type="sphere", friction=-1.0),
                 SceneObject(type="capsule", friction=0.1, motion="orbit")]
    m = build_model(s.cloth, s.behavior)
    cs = colliders.build_colliders(s, m)
    assert [c.name for c in cs] == ["collide_floor", "collide_box", "collide_sphere",
                                    "collide_capsule"]
    assert [c.friction for c in cs] == [0.4, 0.4, 0.4, 0.1]
    assert [getattr(c, "moving", False) for c in cs] == [False, False, False, True]
    assert colliders.build_colliders(scene(scene__floor=False), m) == []


def test_plane_holds_a_rising_sheet_below_it():
    # anti-gravity pushes the sheet up into a horizontal plane from below; it must stay below
    s = scene(cloth__resolution=10, cloth__pinned="none", forces__gravity=False,
              forces__custom="anti_gravity", forces__custom_rate=0.0, scene__floor=False)
    s.objects = [SceneObject(type="plane", center=[0.0, 0.5, 0.0], normal=[0.0, 1.0, 0.0])]
    sim = run(Simulation(s), 60)
    assert sim.state.x[:, 1].max() <= 0.5 - s.scene.thickness + 1e-9
    assert sim.state.x[:, 1].min() > 0.45  # it did rise all the way to the plane
    assert sim.stats()["penetration"] == 0.0


def test_tilted_plane_normal_is_20_degrees_from_vertical():
    n = np.array(colliders.single_object("plane")["normal"])
    assert math.degrees(math.acos(n[1] / np.linalg.norm(n))) == pytest.approx(20.0)


def test_plane_penetration_with_pinned_particles():
    # Found by the soak test: the plane's per-particle sides were matched against the free
    # particles only, which broke as soon as any particle was pinned.
    sim = run(Simulation(scene(scene__object="plane", cloth__pinned="corners",
                               cloth__resolution=10)), 30)
    assert sim.step.penetration(sim.state.x) <= sim.scene.scene.thickness + 1e-3
