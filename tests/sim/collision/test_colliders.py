"""Colliders: shapes, Coulomb friction, moving objects, two-sided planes."""

import math

import numpy as np
import pytest

from cloth_tui.scene import SceneObject
from cloth_tui.sim.collision import colliders
from cloth_tui.sim.model import build_model
from cloth_tui.sim.run.runner import Simulation
from cloth_tui.sim.collision.shapes import shape_of
from ..helpers import run, scene


def shape_collider(m, kind, center=(0.0, 0.0, 0.0), *, friction=0.9, thickness=0.005,
                   moving=False, **keys):
    """The collider of a SceneObject of this type and keys."""
    obj = SceneObject(type=kind, center=list(center), motion="orbit" if moving else "static",
                      **{k: list(v) if isinstance(v, tuple) else v for k, v in keys.items()})
    return colliders.object_collider(m, obj, friction=friction, thickness=thickness)


def one_particle_model():
    s = scene(cloth__resolution=2, cloth__pinned="none")
    return build_model(s.cloth, s.behavior)


# -- kernels on single particles ------------------------------------------------------------
def four(p):
    return np.tile(np.asarray(p, float), (4, 1))


def collide(kind, p, p_prev, friction=0.0, thickness=0.01, **shape):
    """Run one collider on four copies of a particle; return the new position."""
    m = one_particle_model()
    c = shape_collider(m, kind, shape.pop("center", (0.0, 0.0, 0.0)), friction=friction,
                       thickness=thickness, **shape)

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


def contact_then_friction(c, p, p_prev, t=0.0, h=0.01, between=None):
    """The contact pass, optionally something moving the particle (the constraints), then
    friction, as one substep runs them; returns the particle's new position."""
    class S:
        x = four(p)
        x_prev = four(p_prev)
    S.t = t
    c.apply(S, h)
    if between is not None:
        S.x += between
    c.apply_friction(S, h)
    return S.x[0]


def plane(friction):
    return shape_collider(one_particle_model(), "plane", normal=(0.0, 1.0, 0.0),
                          friction=friction, thickness=0.01)


def test_coulomb_friction_sticks_below_mu_times_depth_and_slides_above():
    # On the skin of a horizontal plane, then 3 mm sideways and 4 mm in: depth δ = 4 mm.
    prev, new = (0.0, 0.01, 0.0), (0.003, 0.006, 0.0)
    np.testing.assert_allclose(contact_then_friction(plane(1.0), new, prev), prev, atol=1e-15)
    # μs δ = 2 mm < 3 mm: kinetic, removes μk δ = 0.8 · 0.5 · 4 mm = 1.6 mm of the slide
    np.testing.assert_allclose(contact_then_friction(plane(0.5), new, prev),
                               [0.003 - 0.0016, 0.01, 0.0], atol=1e-15)
    np.testing.assert_allclose(contact_then_friction(plane(0.0), new, prev),
                               [0.003, 0.01, 0.0], atol=1e-15)
    # no contact this substep, no friction
    np.testing.assert_allclose(contact_then_friction(plane(1.0), (0.003, 0.02, 0.0), prev),
                               [0.003, 0.02, 0.0])


def test_friction_resists_what_the_constraints_add_after_the_contact():
    # The contact pass ran on the prediction (1 mm in); then the constraints dragged the
    # particle 0.5 mm sideways. Friction acts on the whole motion, so it holds at μ = 1.
    prev, new = (0.0, 0.01, 0.0), (0.0, 0.009, 0.0)
    drag = np.array([0.0005, 0.0, 0.0])
    np.testing.assert_allclose(contact_then_friction(plane(1.0), new, prev, between=drag),
                               prev, atol=1e-15)
    np.testing.assert_allclose(contact_then_friction(plane(0.0), new, prev, between=drag),
                               [0.0005, 0.01, 0.0], atol=1e-15)


def test_a_moving_object_carries_what_sticks_to_it():
    m = one_particle_model()
    c = shape_collider(m, "box", size=(0.5, 0.2, 0.5), friction=1.0, thickness=0.01,
                       moving=True)
    prev = np.array([0.0, 0.1 + 0.01, 0.0])  # resting on the top face's skin
    # pressed 1 mm in while the box moves ≈ 0.3 mm: within μ·δ, so it moves with the box
    x = contact_then_friction(c, prev - [0.0, 0.001, 0.0], prev, t=1.0, h=0.002)
    shift = colliders.orbit_offset(1.002) - colliders.orbit_offset(1.0)
    np.testing.assert_allclose(x, prev + shift, atol=1e-12)


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
        assert sim.stats().penetration <= sim.scene.scene.thickness + 1e-3


@pytest.mark.parametrize("obj", ["none", "sphere", "box", "plane", "capsule"])
def test_no_particle_sinks_deeper_than_the_skin_after_settling(obj):
    s = scene(cloth__resolution=16, cloth__pinned="none", scene__object=obj,
              behavior__substeps=8)
    sim = run(Simulation(s), 150)
    st = sim.stats()
    assert st.finite and st.max_speed < 0.5
    assert st.penetration <= s.scene.thickness + 1e-3
    expected = {"none": ["collide_floor"]}.get(obj, ["collide_floor", f"collide_{obj}"])
    assert [n for n in st.effects if n.startswith("collide")] == expected


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
    assert sim.stats().penetration <= sim.scene.scene.thickness + 1e-3


def test_orbit_pose_and_static_pose():
    m = one_particle_model()
    c = shape_collider(m, "sphere", (0.0, -0.25, 0.0), moving=True)
    assert c.pose(0.0).center == pytest.approx((0.0, -0.25, 0.0))
    half = c.pose(colliders.ORBIT_PERIOD / 2)
    assert half.center == pytest.approx((0.0, -0.25, 2 * colliders.ORBIT_RADIUS))
    assert c.pose(colliders.ORBIT_PERIOD).center == pytest.approx((0.0, -0.25, 0.0), abs=1e-12)
    still = shape_collider(m, "box", (1.0, 2.0, 3.0), size=(0.1, 0.2, 0.3))
    assert still.pose(5.0) == colliders.ObjectPose("box", {"size": (0.1, 0.2, 0.3)},
                                                    (1.0, 2.0, 3.0))


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
    assert sim.stats().penetration == 0.0


def test_tilted_plane_normal_is_20_degrees_from_vertical():
    n = np.array(shape_of("plane").single_object["normal"])
    assert math.degrees(math.acos(n[1] / np.linalg.norm(n))) == pytest.approx(20.0)


def test_plane_penetration_with_pinned_particles():
    # Found by the soak test: the plane's per-particle sides were matched against the free
    # particles only, which broke as soon as any particle was pinned.
    sim = run(Simulation(scene(scene__object="plane", cloth__pinned="corners",
                               cloth__resolution=10)), 30)
    assert sim.step.penetration(sim.state.x) <= sim.scene.scene.thickness + 1e-3
