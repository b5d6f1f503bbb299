"""The Wang 2011 rows are stored as ARCSim stores them; their physical values are what
ARCSim's own energies make of those numbers. Evaluating ARCSim's formulas (dde.cpp: each
stretching sample doubled; physics.cpp: σ on the Green strain, energy ½σ:G per area, hinge
energy k·l²θ²/(8(A₀+A₁))) on imposed strains and an imposed bend gives the table's stretch,
shear and bending back."""

import numpy as np
import pytest

from cloth_tui.materials.presets import load_presets
from cloth_tui.sim.fabric.bending import bending_energy, bending_stencils
from cloth_tui.sim.grid import Grid
from ..sim.fabric.bent_sheets import cylinder, hinge_sum

WANG = [p for p in load_presets().values() if p.arcsim_stretching and not p.alias_of]


def arcsim_membrane_energy_density(stretching, f):
    """J/m² of ARCSim's data-driven membrane at deformation gradient f (2×2, in the cloth's
    plane): G = ½(FᵀF − I), each stored sample doubled, σ = (k0 G00 + k1 G11, ½k3 G01;
    ½k3 G10, k2 G11 + k1 G00), energy ½ σ:G."""
    k = 2 * np.asarray(stretching, dtype=float)
    g = 0.5 * (f.T @ f - np.eye(2))
    sigma = np.array([[k[0] * g[0, 0] + k[1] * g[1, 1], 0.5 * k[3] * g[0, 1]],
                      [0.5 * k[3] * g[1, 0], k[2] * g[1, 1] + k[1] * g[0, 0]]])
    return 0.5 * float((sigma * g).sum())


@pytest.mark.parametrize("preset", WANG, ids=lambda p: p.name)
def test_the_membrane_is_what_arcsim_makes_of_the_stored_samples(preset):
    eps = 1e-6
    warp = arcsim_membrane_energy_density(preset.arcsim_stretching,
                                          np.array([[1 + eps, 0], [0, 1]]))
    weft = arcsim_membrane_energy_density(preset.arcsim_stretching,
                                          np.array([[1, 0], [0, 1 + eps]]))
    shear = arcsim_membrane_energy_density(preset.arcsim_stretching,
                                           np.array([[1, eps], [0, 1]]))
    assert warp == pytest.approx(0.5 * preset.stretch_warp * eps ** 2, rel=1e-5)
    assert weft == pytest.approx(0.5 * preset.stretch_weft * eps ** 2, rel=1e-5)
    assert shear == pytest.approx(0.5 * preset.shear * eps ** 2, rel=1e-5)


def test_the_bending_is_what_arcsims_hinges_make_of_the_stored_value():
    """On a bend along the grid, ARCSim's hinges and the grid's energy with B = k/4 agree
    wherever both have a stencil: the hinges have none on the two border strips across the
    bend, (rows − 2)/(rows − 1) of the sheet."""
    g = Grid(nx=33, nz=18, width=1.0, length=0.6)
    x = cylinder(g, 0.5, 0)
    for preset in WANG:
        arcsim = preset.arcsim_bending / 8 * hinge_sum(x, g)
        ours = bending_energy(x, bending_stencils(g), preset.bending)
        assert arcsim == pytest.approx(ours * (g.nz - 2) / (g.nz - 1), rel=2e-3)
