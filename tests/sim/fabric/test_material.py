"""A material on the grid: masses, per-edge XPBD compliance and cell shear give the
continuum's energies at every resolution and aspect of the cells; damping per substep does
not depend on the substep."""

import numpy as np
import pytest

from cloth_tui.materials.errors import MaterialError
from cloth_tui.materials.schema import material_from_table
from cloth_tui.sim.fabric.material import (cell_shear_strain, damping_factor,
                                           damping_rate_from_share, lumped_masses,
                                           membrane_energy, pair_compliance, pair_stiffness,
                                           tension_per_width)
from cloth_tui.sim.grid import Grid, grid_pairs
from cloth_tui.scene import Scene
from cloth_tui.sim.model import build_model, grid_edges

DENIM = material_from_table({"preset": "denim"})      # shear well below stretch
SWEAT = material_from_table({"preset": "wang2011-navy-sparkle-sweat"})  # shear > weft
# (nx, nz) from 5×3 to 65×40 cells, cells square and not
GRIDS = [Grid(nx=nx, nz=nz, width=1.0, length=0.6) for nx, nz in ((5, 3), (9, 5), (33, 17),
                                                                  (65, 41), (20, 31))]
STRAIN = 1e-4  # small: the energies compared are the linear theory's


def test_lumped_masses_are_density_times_area_at_every_resolution():
    for g in GRIDS:
        m = lumped_masses(g, DENIM.areal_density)
        assert m.sum() == pytest.approx(DENIM.areal_density * 0.6)
        interior = m.reshape(g.shape)[1:-1, 1:-1]
        assert np.allclose(interior, DENIM.areal_density * g.dx * g.dz)


def stretched(grid, along):
    x = grid.rest_positions()
    x[:, along] *= 1 + STRAIN
    return x


def sheared(grid):
    x = grid.rest_positions()
    x[:, 0] += STRAIN * x[:, 2]  # simple shear: γ = STRAIN
    return x


@pytest.mark.parametrize("shear, grid", [("cells", g) for g in GRIDS] +
                         [("springs", g) for g in GRIDS[:4]],
                         ids=lambda v: f"{v.nx}x{v.nz}" if isinstance(v, Grid) else v)
def test_a_uniform_strain_stores_the_continuums_energy(grid, shear):
    area = grid.area
    warp = membrane_energy(stretched(grid, 0), DENIM, grid, shear)
    weft = membrane_energy(stretched(grid, 2), DENIM, grid, shear)
    shearing = membrane_energy(sheared(grid), DENIM, grid, shear)
    assert warp == pytest.approx(0.5 * DENIM.stretch_warp * STRAIN ** 2 * area, rel=1e-4)
    assert weft == pytest.approx(0.5 * DENIM.stretch_weft * STRAIN ** 2 * area, rel=1e-4)
    assert shearing == pytest.approx(0.5 * DENIM.shear * STRAIN ** 2 * area, rel=1e-4)


def test_cell_shear_holds_a_fabric_stiffer_in_shear_than_in_stretch():
    g = GRIDS[2]
    assert SWEAT.shear > SWEAT.stretch_weft
    assert membrane_energy(sheared(g), SWEAT, g) == pytest.approx(
        0.5 * SWEAT.shear * STRAIN ** 2 * g.area, rel=1e-4)
    assert membrane_energy(stretched(g, 2), SWEAT, g) == pytest.approx(
        0.5 * SWEAT.stretch_weft * STRAIN ** 2 * g.area, rel=1e-4)
    with pytest.raises(MaterialError, match="diagonal springs cannot be that stiff in shear"):
        pair_stiffness(SWEAT, g, grid_pairs(g)["u"], shear="springs")


def test_diagonal_springs_refuse_cells_too_long_for_the_fabric():
    """Along a cell 2.6 times longer than deep, the diagonals alone are stiffer in stretch
    than this fabric's warp: no positive structural stiffness is left."""
    g = GRIDS[4]
    assert g.dx / g.dz > 2.6
    fabric = material_from_table({"areal_density": 0.2, "stretch": 150, "shear": 30,
                                  "bending": 1e-5})
    with pytest.raises(MaterialError, match=r"needs stretch above 208 N/m \(warp\)"):
        membrane_energy(sheared(g), fabric, g, shear="springs")
    square = Grid(nx=20, nz=20, width=1.0, length=1.0)
    assert membrane_energy(sheared(square), fabric, square, shear="springs") > 0


def test_the_cell_shear_strain_ignores_any_stretch_along_the_grid():
    g = GRIDS[1]
    x = g.rest_positions()
    x[:, 0] *= 1.3
    x[:, 2] *= 0.8
    assert np.abs(cell_shear_strain(x, g)).max() < 1e-12
    assert np.allclose(cell_shear_strain(sheared(g), g), STRAIN)


def test_stiffness_is_per_unit_width_so_a_finer_grid_has_softer_edges():
    """The same fabric: an edge of a grid twice as fine stands for half the width at half
    the length, so its stiffness is the same, and the compliance of a border edge (half a
    strip) is twice an interior one's."""
    coarse, fine = (Grid(nx=n, nz=n, width=1.0, length=1.0) for n in (11, 21))
    kc = pair_stiffness(DENIM, coarse, grid_pairs(coarse)["u"])
    kf = pair_stiffness(DENIM, fine, grid_pairs(fine)["u"])
    assert np.isclose(kc.max(), kf.max()) and np.isclose(kc.max(), DENIM.stretch_warp)
    alpha = pair_compliance(DENIM, coarse, grid_pairs(coarse)["u"]).reshape(11, 10)
    assert np.allclose(alpha[0], 2 * alpha[5]) and np.allclose(alpha[-1], alpha[0])


def test_the_grid_of_a_model_is_the_models_sheet():
    scene = Scene().with_values({"cloth.size": [1.2, 0.5], "cloth.resolution": 25})
    model = build_model(scene.cloth, scene.behavior)
    g = Grid.of_model(model)
    assert (g.nx, g.nz) == (model.nx, model.nz) and g.nx != g.nz
    expected = model.rest_positions - [0.0, scene.cloth.height, 0.0]
    assert np.allclose(g.rest_positions(), expected)
    assert np.allclose(lumped_masses(g, 0.2 / g.area), model.mass)  # "area" masses alike


def test_compliance_follows_the_models_edges_in_any_order():
    nx, nz = 9, 6  # a rectangular sheet: rows and columns cannot be mixed up unnoticed
    g = Grid(nx=nx, nz=nz, width=1.0, length=0.6)
    edges, family = grid_edges(nx, nz, (True, True, False))
    order = np.random.default_rng(3).permutation(len(edges))
    edges, family = edges[order], family[order]
    k = pair_stiffness(DENIM, g, edges, shear="springs")
    i, j = np.divmod(edges, nx)
    along_x = (family == 0) & (i[:, 0] == i[:, 1])
    along_z = (family == 0) & (j[:, 0] == j[:, 1])
    inner_x = along_x & (i[:, 0] > 0) & (i[:, 0] < nz - 1)
    inner_z = along_z & (j[:, 0] > 0) & (j[:, 0] < nx - 1)
    # interior structural edges: stretch less what the diagonals add, times strip / length
    assert np.allclose(k[inner_x], (DENIM.stretch_warp - DENIM.shear * (g.dx / g.dz) ** 2)
                       * g.dz / g.dx)
    assert np.allclose(k[inner_z], (DENIM.stretch_weft - DENIM.shear * (g.dz / g.dx) ** 2)
                       * g.dx / g.dz)
    assert np.allclose(k[along_x & ~inner_x], k[inner_x][0] / 2)  # border rows: half strips
    assert np.allclose(k[family == 1], DENIM.shear * (g.dx ** 2 + g.dz ** 2)
                       / (2 * g.dx * g.dz))
    with pytest.raises(ValueError, match="is a diagonal"):
        pair_stiffness(DENIM, g, edges)  # the cells carry shear: no diagonal springs
    bending_pairs, _ = grid_edges(nx, nz, (False, False, True))
    with pytest.raises(ValueError, match="not a neighbour pair"):
        pair_stiffness(DENIM, g, bending_pairs)
    with pytest.raises(ValueError, match="outside the 6×9 grid"):
        pair_stiffness(DENIM, g, [[nx * nz - nx, nx * nz]])


def test_damping_per_substep_does_not_depend_on_the_substeps():
    rate, frame = 1.7, 1 / 60
    for substeps in (1, 4, 37):
        assert damping_factor(rate, frame / substeps) ** substeps == pytest.approx(
            np.exp(-rate * frame), rel=1e-12)
    # behavior.damping's 3 % per 18 ms is 1.69/s
    rate = damping_rate_from_share(0.03, 0.018)
    assert rate == pytest.approx(1.6922, abs=1e-4)
    assert damping_factor(rate, 0.018) == pytest.approx(0.97)
    with pytest.raises(ValueError):
        damping_rate_from_share(1.0, 0.018)


def test_a_uniform_tension_is_the_same_per_unit_width_on_every_edge():
    """Stretched by ε along x, every edge along x, border rows (half strips, half stiffness)
    included, carries stretch·ε per unit width: the number tear_strength will be compared
    with, the same at every resolution."""
    for g in GRIDS:
        pairs = grid_pairs(g)["u"]
        x = stretched(g, 0)
        rest = g.rest_positions()
        extension = (np.linalg.norm(x[pairs[:, 1]] - x[pairs[:, 0]], axis=1)
                     - np.linalg.norm(rest[pairs[:, 1]] - rest[pairs[:, 0]], axis=1))
        force = pair_stiffness(DENIM, g, pairs) * extension
        assert np.allclose(tension_per_width(force, g, pairs), DENIM.stretch_warp * STRAIN,
                           rtol=1e-6)
    with pytest.raises(ValueError, match="is a diagonal"):
        tension_per_width([1.0], GRIDS[0], grid_pairs(GRIDS[0])["diagonal"][:1])
