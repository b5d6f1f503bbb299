"""Mesh colliders: a sheet draped over a mesh read from a file (made here with PyVista)."""

import numpy as np
import pytest

pv = pytest.importorskip("pyvista")

from cloth_tui import meshes  # noqa: E402
from cloth_tui.scene import Scene, SceneObject  # noqa: E402
from cloth_tui.sim import pipeline  # noqa: E402
from cloth_tui.sim.collision.colliders import ShapeCollider  # noqa: E402
from cloth_tui.sim.run.runner import Simulation  # noqa: E402

from ..helpers import run, scene  # noqa: E402

RING, TUBE = 0.25, 0.08  # torus radii, m
THICKNESS = 0.005


@pytest.fixture(scope="module")
def torus_stl(tmp_path_factory):
    """A torus about z (as PyVista makes it), saved as STL."""
    path = tmp_path_factory.mktemp("mesh") / "torus.stl"
    pv.ParametricTorus(ringradius=RING, crosssectionradius=TUBE, u_res=64, v_res=32,
                       w_res=2).triangulate().clean().save(path)
    return path


@pytest.fixture(scope="module")
def sphere_stl(tmp_path_factory):
    path = tmp_path_factory.mktemp("mesh") / "sphere.stl"
    pv.Sphere(radius=0.25, theta_resolution=90, phi_resolution=60).triangulate().save(path)
    return path


def mesh_scene(path, **obj) -> Scene:
    s = scene(cloth__pinned="none", cloth__resolution=26, cloth__height=0.3,
              behavior__substeps=8, scene__thickness=THICKNESS)
    s.objects = [SceneObject(type="mesh", path=str(path), **obj)]
    return s.with_values({})  # validated


def torus_distance(x, center):
    """Exact signed distance from the torus lying flat (axis y) at `center`."""
    q = x - np.asarray(center)
    return np.hypot(np.hypot(q[:, 0], q[:, 2]) - RING, q[:, 1]) - TUBE


def test_sheet_settles_on_a_torus_without_entering_it(torus_stl):
    center = [0.0, -0.1, 0.0]
    s = mesh_scene(torus_stl, center=center, rotation=[90.0, 0.0, 0.0])
    sim = run(Simulation(s), 240)
    st = sim.stats()
    assert st.finite and st.recoveries == 0
    assert "collide_mesh" in st.effects
    assert st.penetration <= THICKNESS + 1e-3
    d = torus_distance(sim.state.x, center)
    assert d.min() > -1e-3  # against the true torus, not only the grid
    resting = d < THICKNESS + 3e-3
    assert resting.sum() > 20  # the sheet lies on it (else the test proves nothing)
    assert st.max_speed < 0.2  # and has settled


def test_rotation_turns_the_mesh(torus_stl):
    """Without the 90° about x the torus stands on edge: the sheet touches a different set."""
    flat = mesh_scene(torus_stl, center=[0.0, -0.1, 0.0], rotation=[90.0, 0.0, 0.0])
    upright = mesh_scene(torus_stl, center=[0.0, -0.1, 0.0])
    m = Simulation(flat).model
    f_flat = meshes.field_for(flat.objects[0], m.spacing, THICKNESS)
    f_up = meshes.field_for(upright.objects[0], m.spacing, THICKNESS)
    assert np.ptp(f_flat.surface.vertices[:, 1]) == pytest.approx(2 * TUBE, rel=0.02)
    assert np.ptp(f_up.surface.vertices[:, 1]) == pytest.approx(2 * (RING + TUBE), rel=0.02)


def test_a_sphere_mesh_holds_the_sheet_where_the_analytic_sphere_does(sphere_stl):
    """Where the sheet rests on the sphere, the mesh's grid keeps it within 2 mm of the
    analytic collider's distance from the centre. (Positions along the surface are not
    compared: the draped skirt folds chaotically, so a sub-millimetre difference in the contact
    grows to centimetres of sliding within a second.)"""
    center = np.array([0.0, -0.25, 0.0])
    # (pbd: its stretchier sheet wraps the sphere with more particles in contact to compare)
    analytic = scene(cloth__pinned="none", cloth__resolution=26, cloth__height=0.3,
                     behavior__substeps=8, scene__thickness=THICKNESS, behavior__solver="pbd")
    analytic.objects = [SceneObject(type="sphere", center=list(center), radius=0.25)]
    a = run(Simulation(analytic.with_values({})), 60)
    m = run(Simulation(mesh_scene(sphere_stl, center=list(center)).with_value(
        "behavior.solver", "pbd")), 60)
    assert list(m.stats().effects) == [e if e != "collide_sphere" else "collide_mesh"
                                    for e in a.stats().effects]
    ra = np.linalg.norm(a.state.x - center, axis=1)
    rm = np.linalg.norm(m.state.x - center, axis=1)
    resting = (ra < 0.25 + THICKNESS + 1e-3) & (rm < 0.25 + THICKNESS + 1e-3)
    assert resting.sum() > 10
    assert np.abs(rm - ra)[resting].max() < 2e-3
    assert rm.min() == pytest.approx(ra.min(), abs=2e-3)
    apex = a.model.nx // 2 * (a.model.nx + 1)  # the centre particle, on top of the sphere
    assert m.state.x[apex, 1] == pytest.approx(a.state.x[apex, 1], abs=2e-3)


def test_scale_and_friction_reach_the_collider(sphere_stl):
    s = mesh_scene(sphere_stl, center=[0.0, -0.25, 0.0], scale=0.5, friction=0.2)
    step = pipeline.build(s, Simulation(s).model)
    (mesh,) = [c for c in step.colliders if isinstance(c, ShapeCollider) and c.shape.name == "mesh"]
    assert mesh.friction == 0.2
    r = np.linalg.norm(mesh.parameters["surface"].vertices, axis=1)
    assert r.max() == pytest.approx(0.125, rel=1e-3)
    assert mesh.signed_distance(np.array([[0.0, -0.25 + 0.15, 0.0]]))[0] == \
        pytest.approx(0.025, abs=2e-3)


def test_an_orbiting_mesh_carries_its_grid_along(sphere_stl):
    s = mesh_scene(sphere_stl, center=[0.0, -0.25, 0.0], motion="orbit")
    sim = Simulation(s)
    run(sim, 30)
    (mesh,) = [c for c in sim.step.colliders
               if isinstance(c, ShapeCollider) and c.shape.name == "mesh"]
    c = mesh.center_at(sim.state.t)
    assert not np.allclose(c, [0.0, -0.25, 0.0])
    top = c + [0.0, 0.25, 0.0]
    assert mesh.signed_distance(top[None, :])[0] == pytest.approx(0.0, abs=2e-3)
    assert sim.snapshot().objects[0].center == pytest.approx(tuple(c))
