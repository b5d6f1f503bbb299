"""The material's bending as the solver projects it: the stencils' vector constraints
(fabric_solve.project_stencils) store the plate energy (B/2)∫κ² dA of an imposed cylinder
at any angle to the grid, and push as the bending energy's gradient."""

import math

import numpy as np
import pytest

from cloth_tui.scene import Scene
from cloth_tui.sim.fabric.bending import bending_gradient
from cloth_tui.sim.solvers.xpbd.fabric_constraints import (ProjectFabric, fabric_energy,
                                                            fabric_force_energy, project_stencils)
from cloth_tui.sim.model import build_model

from .bent_sheets import cylinder

RIGIDITY = 1e-4  # N·m
RADIUS = 0.5  # m


def _model(resolution=(33, 17), size=(1.0, 0.5)):
    scene = Scene().with_values({
        "behavior.solver": "xpbd", "cloth.pinned": "none", "cloth.size": list(size),
        "cloth.resolution": list(resolution),
        "material": {"areal_density": 0.2, "stretch": 500.0, "shear": 20.0,
                     "bending": RIGIDITY}})
    return build_model(scene.cloth, scene.behavior, scene.pins, scene.material.material)


def _one_stencil_pass(model, x, h):
    """One pass of the wired bending projection from λ = 0 at substep h; its solver."""
    solver = ProjectFabric(model, 1, h)
    f = model.fabric
    project_stencils(x, model.inv_mass, f.stencils.particles, f.stencils.coeffs,
                     solver.stencil_alive, solver.stencil_lambdas, solver.stencil_alpha_t,
                     True, 1)
    return solver


@pytest.mark.parametrize("degrees", [0, 30, 45])
def test_an_imposed_cylinders_energy_through_the_wired_constraints_is_the_plates(degrees):
    m = _model()
    x = cylinder(m.fabric.grid, RADIUS, degrees)
    plate = 0.5 * RIGIDITY * m.fabric.grid.area / RADIUS ** 2
    # by the constraints' own Σ |C|²/(2α), as the solve minimises it
    assert fabric_energy(x, m)["bending"] == pytest.approx(plate, rel=0.05)
    # and by the multipliers one projection leaves, ½ Σ α |λ/h²|²: at a substep short
    # enough that α̃ dwarfs the particles' weight, λ = −C/α̃, the constraint's force
    solver = _one_stencil_pass(m, x.copy(), 1e-7)
    solver.edges.lambdas[:] = 0.0
    assert fabric_force_energy(solver, 1e-7) == pytest.approx(plate, rel=0.05)


def test_the_cylinders_energy_is_the_same_at_every_angle_to_the_grid():
    m = _model()
    energies = [fabric_energy(cylinder(m.fabric.grid, RADIUS, d), m)["bending"]
                for d in (0, 30, 45, 60, 90)]
    assert max(energies) / min(energies) < 1.01


def test_a_projection_moves_the_particles_down_the_bending_energys_gradient():
    # From λ = 0 with α̃ ≫ Σ w c², one pass moves each particle by −h² M⁻¹ ∇E: the
    # implicit step's first correction, so the constraints are the energy's.
    m = _model((12, 9), (0.6, 0.4))
    x0 = cylinder(m.fabric.grid, 0.3, 30)
    h = 1e-4  # α̃ is then ~3e5 × Σ w c², and the moves far above round-off
    x = x0.copy()
    _one_stencil_pass(m, x, h)
    expected = -h * h * m.inv_mass[:, None] * bending_gradient(x0, m.fabric.stencils,
                                                                RIGIDITY)
    np.testing.assert_allclose(x - x0, expected, rtol=1e-3, atol=1e-5 * np.abs(expected).max())
    assert np.abs(expected).max() > 0


def test_a_flat_or_rigidly_moved_sheet_has_no_bending_energy():
    m = _model((10, 7), (0.5, 0.3))
    x = m.rest_positions.copy()
    turn = math.radians(40)
    rot = np.array([[math.cos(turn), 0, math.sin(turn)], [0, 1, 0],
                    [-math.sin(turn), 0, math.cos(turn)]])
    moved = x @ rot.T + [0.3, -1.0, 2.0]
    energy = fabric_energy(moved, m)
    assert energy["bending"] < 1e-20 and energy["shear"] < 1e-20 and energy["stretch"] < 1e-20


@pytest.mark.parametrize("iterations", [3, 8, 24])
def test_a_settled_strip_bends_as_its_material_whatever_the_iterations(iterations,
                                                                        monkeypatch):
    """The stencils' warm start: at rest the bending solve starts at its answer, so a
    clamped strip whose bending per step is stiff against its masses settles at the same
    tip drop at 3, 8 or 24 passes. (Each substep's λ started from 0, the unconverged passes
    left its tip 17 % too far down at 8 passes.)"""
    from cloth_tui.lab import clamped
    from cloth_tui.lab.elastica import cantilever
    from cloth_tui.lab.study import lab_material

    denim = lab_material("denim")
    length = clamped.strip_for_load(2.0, denim)
    monkeypatch.setattr(clamped, "ITERATIONS", iterations)
    monkeypatch.setattr(clamped, "MAX_BENDING_PER_STEP", 2.0)  # stiff: 20 substeps a frame
    r = clamped.settle_clamped(length, 10, denim)
    assert r["drop"] / length == pytest.approx(cantilever(2.0).tip_drop, rel=0.01)
