"""A scene's material wired into the model and the solver: masses, the stiffness of each
edge, per-constraint α̃ in both projection paths, no tethers, damping as a decay rate."""

import math

import numpy as np
import pytest

from cloth_tui.materials.presets import get_preset
from cloth_tui.scene import Scene
from cloth_tui.sim import grid_sweeps
from cloth_tui.sim.solvers.xpbd import constraints as xpbd
from cloth_tui.sim.fabric.material import ALONG_X, ALONG_Z, pair_compliance, pair_kinds, strip_width
from cloth_tui.sim.model import build_model
from cloth_tui.sim.run.runner import Simulation

CUSTOM = {"areal_density": 0.2, "stretch": [100.0, 50.0], "shear": 10.0, "bending": 0.0,
          "damping": 5.0}


def fabric_scene(material="denim", **values) -> Scene:
    table = {"preset": material} if isinstance(material, str) else material
    return Scene().with_values({"behavior.solver": "xpbd", "behavior.adaptive": False,
                                "material": table, **values})


def _model(scene: Scene):
    return build_model(scene.cloth, scene.behavior, scene.pins, scene.material.material)


@pytest.mark.parametrize("size, resolution", [(1.0, 5), (1.0, 16), (1.0, 33), (1.0, 64),
                                              ([0.6, 1.3], [7, 19]), ([2.0, 0.5], 40)])
def test_masses_sum_to_density_times_area_at_every_resolution(size, resolution):
    scene = fabric_scene("denim", **{"cloth.size": size, "cloth.resolution": resolution})
    m = _model(scene)
    w, length = scene.cloth.dimensions()
    assert m.mass.sum() == pytest.approx(get_preset("denim").areal_density * w * length,
                                         rel=1e-12)
    # and not cloth.mass, which only the original's unitless sheet uses
    assert m.mass.sum() != pytest.approx(scene.cloth.mass)


def test_a_material_builds_structural_edges_with_their_own_compliance_and_no_tethers():
    scene = fabric_scene("denim", **{"cloth.resolution": [9, 6], "cloth.size": [1.0, 0.5]})
    m = _model(scene)
    kind, _, _ = pair_kinds(m.fabric.grid, m.edges)
    assert set(kind.tolist()) == {ALONG_X, ALONG_Z}  # no diagonals, no two-apart "bending"
    np.testing.assert_array_equal(m.fabric.compliance,
                                  pair_compliance(scene.material.material, m.fabric.grid,
                                                  m.edges))
    assert m.tether_pin is None and len(m.pinned) == 4
    assert m.fabric.num_cells == 8 * 5 and m.fabric.num_stencils > 0
    original = build_model(scene.cloth, scene.behavior, scene.pins)
    assert original.fabric is None and original.tether_pin is not None


def _strip(along: str, strain: float = 0.01):
    """A 1 m × 0.2 m strip, no gravity, held at both ends, one end moved by `strain`."""
    ends = [{"cols": [0, 0]}, {"cols": [-1, -1]}] if along == "x" else \
        [{"rows": [0, 0]}, {"rows": [-1, -1]}]
    ends[1]["offset"] = [strain, 0.0, 0.0] if along == "x" else [0.0, 0.0, strain]
    scene = fabric_scene(CUSTOM, **{
        "cloth.size": [1.0, 0.2] if along == "x" else [0.2, 1.0],
        "cloth.resolution": [21, 5] if along == "x" else [5, 21], "cloth.pinned": "none",
        "forces.gravity": False, "scene.floor": False, "behavior.substeps": 10,
        "behavior.iterations": 20, "pins": ends})
    sim = Simulation(scene)
    for _ in range(180):
        sim.advance_frame()
    return sim


@pytest.mark.parametrize("along, stretch", [("x", 100.0), ("z", 50.0)])
def test_a_stretched_strip_shows_the_materials_stiffness_in_every_edge(along, stretch):
    # warp along x, weft along z: each edge's force over its extension, per unit width of
    # the strip it stands for, is the material's N/m; so is the tension across the strip.
    sim = _strip(along)
    m, g = sim.model, sim.model.fabric.grid
    force = -sim.step.solver.lambdas / sim.step.h ** 2  # λ is accumulated for C = L0 − L
    length = np.linalg.norm(sim.state.x[m.edges[:, 1]] - sim.state.x[m.edges[:, 0]], axis=1)
    kind, i, j = pair_kinds(g, m.edges)
    sel = kind == (ALONG_X if along == "x" else ALONG_Z)
    extension = (length - m.rest_length)[sel]
    spacing = g.dx if along == "x" else g.dz
    assert extension == pytest.approx(0.01 * spacing, rel=1e-5)
    per_width = force[sel] / extension * spacing / strip_width(g, m.edges[sel])
    assert per_width == pytest.approx(stretch, rel=1e-6)
    middle = (j[sel] == (g.nx - 1) // 2) if along == "x" else (i[sel] == (g.nz - 1) // 2)
    width = g.length if along == "x" else g.width
    assert force[sel][middle].sum() / width / 0.01 == pytest.approx(stretch, rel=1e-5)


@pytest.mark.parametrize("n", [5, 8, [7, 13], [13, 6]])
@pytest.mark.parametrize("kernel", [grid_sweeps.sweep_grid_colors,
                                    grid_sweeps.sweep_grid_colors_parallel])
def test_sweeps_with_an_alpha_per_edge_match_the_plain_loop(n, kernel):
    m = _model(fabric_scene("denim", **{"cloth.resolution": n, "cloth.pinned": "one_edge"}))
    rng = np.random.default_rng(m.num_particles)
    alpha_t = rng.uniform(1e-4, 1.0, m.num_constraints)  # each edge its own, widely apart
    x0 = m.rest_positions + rng.normal(scale=0.01, size=m.rest_positions.shape)
    a, b = x0.copy(), x0.copy()
    alive = np.ones(m.num_constraints, np.uint8)
    lam_ref, lam = np.zeros(m.num_constraints), np.zeros(m.num_constraints)
    xpbd.project_constraints_per_edge(a, m.inv_mass, m.edges, m.rest_length, alive, lam_ref,
                                      alpha_t, 3, True)
    plan = grid_sweeps.plan_sweeps(m.nx, m.nz, m.edges, m.color_offsets, m.rest_length,
                                   m.inv_mass)
    scratch = plan.scratch()
    grid_sweeps.sweep(kernel, plan, scratch, b, alive, lam, 0.0, 2,
                      grid_sweeps.slot_alphas(plan, alpha_t))
    grid_sweeps.sweep(kernel, plan, scratch, b, alive, lam, 0.0, 1,
                      grid_sweeps.slot_alphas(plan, alpha_t), fresh=False)  # λ goes on
    np.testing.assert_allclose(b, a, atol=1e-12)
    np.testing.assert_allclose(lam, lam_ref, atol=1e-12)
    assert np.abs(b - x0).max() > 1e-4


@pytest.mark.parametrize("substeps", [3, 10, 40])
def test_the_materials_damping_is_a_decay_rate_whatever_the_substeps(substeps):
    # A free sheet, no gravity, moving rigidly: its speed after 0.5 s is exp(−γ·0.5).
    scene = fabric_scene(CUSTOM | {"damping": 2.0}, **{
        "cloth.pinned": "none", "forces.gravity": False, "scene.floor": False,
        "cloth.resolution": 8, "behavior.substeps": substeps})
    sim = Simulation(scene)
    sim.state.v[:] = [0.0, 0.0, 0.3]
    for _ in range(30):
        sim.advance_frame()
    assert np.abs(sim.state.v[:, 2] - 0.3 * math.exp(-2.0 * 0.5)).max() < 1e-9


def test_the_runners_energy_with_a_material_counts_its_shear_and_bending_too():
    # A denim sheet swinging from one edge bends and shears: the energy the runner reports
    # (and the numerical damping reads) holds every family's ½αf², not the edges' alone.
    from cloth_tui.sim.solvers.xpbd.fabric_constraints import fabric_force_energy
    from cloth_tui.sim.run.measures import (gravitational_energy, kinetic_energy, per_constraint,
                                            xpbd_elastic_energy)
    scene = fabric_scene("denim", **{"cloth.pinned": "one_edge", "cloth.resolution": 12,
                                     "scene.floor": False, "behavior.substeps": 8})
    sim = Simulation(scene)
    for _ in range(20):
        sim.advance_frame()
    solver, m, st = sim.step.solver, sim.model, sim.state
    reported = sim.stats().energy
    elastic = fabric_force_energy(solver.projection, sim.step.h)
    assert reported == pytest.approx(kinetic_energy(m, st)
                                     + gravitational_energy(m, st, scene) + elastic)
    edges_only = (kinetic_energy(m, st) + gravitational_energy(m, st, scene)
                  + xpbd_elastic_energy(solver.lambdas,
                                        per_constraint(solver.alpha_tilde, m.num_constraints),
                                        sim.step.h))
    # the cells' and stencils' share is there, and is no rounding
    assert reported - edges_only > 1e-3 * elastic > 0.0
