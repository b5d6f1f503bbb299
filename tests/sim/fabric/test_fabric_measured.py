"""A measured preset in the solver: a strip held at 10 % strain pulls with the measured
tension (its edges stiffen with strain), and folds along the warp, the bias and the weft
store the three measured rigidities; a material of typed numbers keeps the linear model."""

import dataclasses
import math

import numpy as np
import pytest

from cloth_tui.lab import clamped
from cloth_tui.lab.elastica import cantilever
from cloth_tui.lab.strips import strip_scene

from cloth_tui.materials.presets import get_preset
from cloth_tui.materials.schema import material_from_table
from cloth_tui.scene import Scene
from cloth_tui.sim.fabric.material import (ALONG_X, ALONG_Z, pair_compliance, pair_kinds,
                                           strip_width)
from cloth_tui.sim.grid import Grid
from cloth_tui.sim.model import build_model
from cloth_tui.sim.run.runner import Simulation
from cloth_tui.sim.solvers.xpbd.fabric_constraints import fabric_energy

from .bent_sheets import cylinder, hinge_sum

# a woven, an interlock knit whose weft stiffens ×9 by 10 %, a sweat knit whose weft ×50
STRETCH_PRESETS = ("denim", "jersey", "wang2011-navy-sparkle-sweat")
# the three with the most unequal folds
BENDING_PRESETS = ("denim", "wang2011-pink-ribbon-brown", "wang2011-ivory-rib-knit")


def _strip(table, along: str, strain: float):
    """A 1 m × 0.2 m strip, no gravity, held by its end rows, one end moved by `strain`;
    substeps and passes enough for denim's weft, the stiffest, to converge."""
    ends = [{"cols": [0, 0]}, {"cols": [-1, -1]}] if along == "x" else \
        [{"rows": [0, 0]}, {"rows": [-1, -1]}]
    ends[1]["offset"] = [strain, 0.0, 0.0] if along == "x" else [0.0, 0.0, strain]
    scene = Scene().with_values({
        "behavior.solver": "xpbd", "behavior.adaptive": False, "material": table,
        "cloth.size": [1.0, 0.2] if along == "x" else [0.2, 1.0],
        "cloth.resolution": [21, 5] if along == "x" else [5, 21], "cloth.pinned": "none",
        "forces.gravity": False, "scene.floor": False, "behavior.substeps": 20,
        "behavior.iterations": 20, "pins": ends})
    sim = Simulation(scene)
    for _ in range(60):
        sim.advance_frame()
    return sim


def _tension(sim, along: str) -> float:
    """N/m: the force across the strip's middle over its width."""
    m, g = sim.model, sim.model.fabric.grid
    force = -sim.step.solver.lambdas / sim.step.h ** 2  # λ is accumulated for C = L0 − L
    kind, i, j = pair_kinds(g, m.edges)
    sel = kind == (ALONG_X if along == "x" else ALONG_Z)
    middle = (j[sel] == (g.nx - 1) // 2) if along == "x" else (i[sel] == (g.nz - 1) // 2)
    return float(force[sel][middle].sum()) / (g.length if along == "x" else g.width)


@pytest.mark.parametrize("along", ["x", "z"])
@pytest.mark.parametrize("preset", STRETCH_PRESETS)
def test_a_strip_held_at_10_percent_pulls_with_the_measured_tension(preset, along):
    table = {"preset": preset, "damping": 5.0}
    warp, weft = material_from_table(table).stretch_curves
    measured = (warp if along == "x" else weft).tension(0.1)
    assert _tension(_strip(table, along, 0.1), along) == pytest.approx(measured, rel=0.05)


def test_typed_stretch_is_linear_as_before():
    p = get_preset("jersey")
    table = {"preset": "jersey", "damping": 5.0, "stretch": [p.stretch_warp, p.stretch_weft]}
    sim = _strip(table, "z", 0.1)
    assert sim.model.fabric.stretch is None
    assert _tension(sim, "z") == pytest.approx(p.stretch_weft * 0.1, rel=0.01)
    # the curve's tension at 10 % is ×9 that: the two are told apart
    assert p.stretch_curves[1].tension(0.1) > 5 * p.stretch_weft * 0.1


def test_a_material_of_typed_numbers_builds_the_constraints_it_built_before():
    table = {"areal_density": 0.3, "stretch": [400.0, 900.0], "shear": 20.0,
             "bending": 5e-5}
    scene = Scene().with_values({"behavior.solver": "xpbd", "cloth.resolution": [9, 7],
                                 "material": table})
    m = build_model(scene.cloth, scene.behavior, scene.pins, scene.material.material)
    assert m.fabric.stretch is None
    np.testing.assert_array_equal(m.fabric.compliance,
                                  pair_compliance(scene.material.material, m.fabric.grid,
                                                  m.edges))
    np.testing.assert_array_equal(m.fabric.stencil_compliance,
                                  1.0 / (5e-5 * m.fabric.stencils.weights))


def _bent_model(preset, rows=25, cols=25):
    scene = Scene().with_values({"behavior.solver": "xpbd", "cloth.pinned": "none",
                                 "cloth.size": [0.5, 0.5], "cloth.resolution": [cols, rows],
                                 "material": {"preset": preset}})
    return build_model(scene.cloth, scene.behavior, scene.pins, scene.material.material)


@pytest.mark.parametrize("degrees", [0, 45, 90])
@pytest.mark.parametrize("preset", BENDING_PRESETS)
def test_a_fold_at_0_45_or_90_degrees_to_the_warp_stores_its_measured_rigidity(preset,
                                                                               degrees):
    m = _bent_model(preset)
    g, radius = m.fabric.grid, 0.4
    # a cylinder whose axis, the fold line, makes `degrees` with the warp (x)
    energy = fabric_energy(cylinder(g, radius, degrees), m)["bending"]
    rigidity = 2 * energy * radius ** 2 / g.area
    folds = get_preset(preset).bending_by_direction
    assert rigidity == pytest.approx({0: folds.fold_0, 45: folds.fold_45,
                                      90: folds.fold_90}[degrees], rel=0.05)


def test_the_folds_are_arcsims_rows_by_the_angle_of_their_hinges():
    """ARCSim looks each hinge's stiffness up by the angle of the hinge edge: a cylinder
    whose axis is along x folds only the edges along x (the one-diagonal triangulation of a
    cell stays flat), so ARCSim bends it with its 0° row; along z, the 90° row."""
    p = get_preset("denim")
    m = _bent_model("denim", rows=18, cols=33)
    g = m.fabric.grid
    for degrees, k, across in ((0, p.arcsim_bending, g.nz), (90, 4 * p.bending_by_direction
                                                             .fold_90, g.nx)):
        x = cylinder(g, 0.5, degrees)
        arcsim = k / 8 * hinge_sum(x, g)
        ours = fabric_energy(x, m)["bending"]
        # the hinges have no stencil on the two border strips across the bend
        assert arcsim == pytest.approx(ours * (across - 2) / (across - 1), rel=5e-3)


def test_the_edges_stand_for_their_strips_as_the_linear_compliance_does():
    from cloth_tui.sim.fabric.stretch_curve import edge_stretch
    material = material_from_table({"preset": "jersey"})
    g = Grid(nx=9, nz=6, width=1.0, length=0.5)
    m = _bent_model("jersey", rows=6, cols=9)
    s = edge_stretch(material, g, m.edges)
    np.testing.assert_allclose(s.rest_over_width / s.low,
                               pair_compliance(material, g, m.edges), rtol=1e-12)
    kind, _, _ = pair_kinds(g, m.edges)
    assert (s.rest_over_width * strip_width(g, m.edges))[kind == ALONG_X] == \
        pytest.approx(g.dx)


def _clamped_drop(preset: str, along: str, load: float = 2.0, links: int = 10) -> float:
    """δ/L of a strip of `preset` cut along x (warp) or z (weft), clamped by its first three
    rows of particles as the lab clamps, settled for six periods of its first mode; its free
    length puts wL³/B = `load` for the rigidity of its own curvature."""
    m = material_from_table({"preset": preset})
    folds = m.bending_by_direction
    # the rigidity of its own curvature alone: the lab's formulas then size this strip
    own = dataclasses.replace(m, bending=folds.fold_90 if along == "x" else folds.fold_0,
                              bending_by_direction=None)
    length = clamped.strip_for_load(load, own)
    h = clamped.free_length_spacing(length, links)
    n = links + clamped.HELD_COLUMNS
    across = min(clamped.MAX_ROWS, max(2, round(clamped.STRIP_WIDTH / length * links) + 1))
    long_side = (n - 1) * h
    held = [0, clamped.HELD_COLUMNS - 1]
    scene = strip_scene(
        size=[long_side, clamped.STRIP_WIDTH] if along == "x" else [clamped.STRIP_WIDTH,
                                                                    long_side],
        resolution=[n, across] if along == "x" else [across, n],
        pins=[{"cols": held}] if along == "x" else [{"rows": held}],
        behavior={"solver": "xpbd", "iterations": clamped.ITERATIONS, "frame_rate": 60.0,
                  "substeps": clamped.substeps_for(h, own, 60.0)},
        material_section={"preset": preset,
                          "damping": clamped.settling_damping(length, own)})
    sim = Simulation(scene)
    for _ in range(math.ceil(6 * clamped.first_mode_period(length, own) * 60.0)):
        sim.advance_frame()
    y = sim.state.x[:, 1].reshape((across, n) if along == "x" else (n, across))
    if along == "z":
        y = y.T
    return float(np.mean(y[:, clamped.HELD_COLUMNS - 1] - y[:, -1])) / length


@pytest.mark.parametrize("along", ["x", "z"])
@pytest.mark.parametrize("preset", ["denim", "wang2011-pink-ribbon-brown"])
def test_a_clamped_strip_hangs_as_the_elastica_of_its_own_directions_rigidity(preset, along):
    # denim's warp strip is 1.5× as stiff as its weft strip, pink-ribbon-brown's 0.5×: with
    # one rigidity for both, one of each pair would miss by a third or more
    assert _clamped_drop(preset, along) == pytest.approx(cantilever(2.0).tip_drop, rel=0.02)


def test_the_accuracy_control_judges_a_stiffening_fabric_by_the_compliance_in_force():
    # a sweat knit hung by two clips stretches to ~20 % by its corners, where its weft is
    # ×50 as stiff as at rest: judged by its slack α the solve never looks converged and the
    # control runs at its cap
    sim = Simulation(Scene().with_values({
        "cloth.size": 1.0, "cloth.resolution": 17, "cloth.pinned": "none",
        "cloth.height": 1.0, "scene.floor": False, "behavior.solver": "xpbd",
        "behavior.adaptive": True,
        "material": {"preset": "wang2011-navy-sparkle-sweat", "damping": 2.0},
        "pins": [{"rows": [0, 0], "cols": [0, 1]}, {"rows": [0, 0], "cols": [-2, -1]}]}))
    used = []
    for _ in range(60):
        sim.advance_frame()
        used.append(sim.stats().substeps_used)
    stats = sim.stats()
    assert stats.finite and stats.tolerance_met
    assert max(used[30:]) <= 12  # 6 measured; judged by the slack α, 35 and rising
    assert 0.1 < stats.max_stretch < 0.3  # stretched well into its stiffening


def test_tearing_asks_the_solve_for_the_tension_where_the_curve_is_steep():
    # the error that knows the tension to a tenth of the strength is a tenth of the strength
    # over the stiffness there: for jersey at 100 N/m, ×20 its stiffness at rest
    from cloth_tui.sim.effects.tearing import TEAR_FORCE_SHARE, strength_tolerance
    p = get_preset("jersey")
    tolerances = {}
    for label, extra in (("curve", {}), ("linear", {"stretch": [p.stretch_warp,
                                                               p.stretch_weft]})):
        scene = Scene().with_values({
            "behavior.solver": "xpbd", "behavior.tear": True, "cloth.resolution": 9,
            "material": {"preset": "jersey", "tear_strength": 100.0, **extra}})
        m = build_model(scene.cloth, scene.behavior, scene.pins, scene.material.material)
        tolerances[label] = strength_tolerance(m, 100.0)
    weft = p.stretch_curves[1]
    assert tolerances["curve"] == pytest.approx(
        TEAR_FORCE_SHARE * 100.0 / weft.tangent(weft.strain_at(100.0)))
    assert tolerances["linear"] == pytest.approx(TEAR_FORCE_SHARE * 100.0 / p.stretch_weft)
    assert tolerances["curve"] < tolerances["linear"] / 10
