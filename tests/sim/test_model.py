import numpy as np
import pytest

from cloth_tui.scene import Scene
from cloth_tui.sim.model import (BENDING, SHEAR, STRUCTURAL, build_model, grid_triangles,
                                 pinned_indices)


def model_for(**cloth):
    s = Scene()
    for k, v in cloth.items():
        setattr(s.cloth, k, v)
    return build_model(s.cloth, s.behavior)


def test_constraint_counts_per_family():
    n = 10
    m = model_for(resolution=n)
    counts = np.bincount(m.family, minlength=3)
    assert counts[STRUCTURAL] == 2 * n * (n - 1)
    assert counts[SHEAR] == 2 * (n - 1) ** 2
    assert counts[BENDING] == 2 * n * (n - 2)


def test_rest_lengths_match_grid_spacing():
    m = model_for(resolution=11, size=2.0)
    h = 0.2
    expect = {STRUCTURAL: h, SHEAR: h * np.sqrt(2), BENDING: 2 * h}
    for fam, length in expect.items():
        np.testing.assert_allclose(m.rest_length[m.family == fam], length)


def test_colours_are_conflict_free():
    m = model_for(resolution=17)
    off = m.color_offsets
    assert off[-1] == m.num_constraints
    for c in range(len(off) - 1):
        e = m.edges[off[c]:off[c + 1]]
        assert len(np.unique(e.ravel())) == 2 * len(e), f"colour {c} shares a particle"


@pytest.mark.parametrize("families", [(False, True, True), (True, False, False), (False,) * 3])
def test_families_switch_off(families):
    s = Scene()
    s.behavior.structural, s.behavior.shear, s.behavior.bending = families
    m = build_model(s.cloth, s.behavior)
    present = set(np.unique(m.family).tolist())
    assert present == {f for f, on in enumerate(families) if on}


def test_pin_modes_pin_documented_particles():
    n = 5
    idx = np.arange(n * n).reshape(n, n)
    assert set(pinned_indices(n, "none")) == set()
    assert set(pinned_indices(n, "corners")) == {0, n - 1, n * (n - 1), n * n - 1}
    assert set(pinned_indices(n, "one_edge")) == set(idx[0])
    assert set(pinned_indices(n, "two_edges")) == set(idx[0]) | set(idx[-1])
    border = set(idx[0]) | set(idx[-1]) | set(idx[:, 0]) | set(idx[:, -1])
    assert set(pinned_indices(n, "four_edges")) == border
    r1 = pinned_indices(20, "random", seed=3, fraction=0.1)
    assert len(r1) == 40
    np.testing.assert_array_equal(r1, pinned_indices(20, "random", seed=3, fraction=0.1))
    assert not np.array_equal(r1, pinned_indices(20, "random", seed=4, fraction=0.1))


def test_pinned_particles_have_zero_inverse_mass_and_mass_sums():
    m = model_for(resolution=8, mass=0.4)
    assert np.all(m.inv_mass[m.pinned] == 0)
    assert m.mass.sum() == pytest.approx(0.4)


def test_masses_by_area_edges_half_corners_quarter():
    n = 6
    m = model_for(resolution=n, mass=0.5)
    grid = m.mass.reshape(n, n)
    interior = grid[2, 3]
    np.testing.assert_allclose(grid[1:-1, 1:-1], interior)
    np.testing.assert_allclose(grid[0, 1:-1], interior / 2)   # edges
    np.testing.assert_allclose(grid[1:-1, -1], interior / 2)
    np.testing.assert_allclose(grid[[0, 0, -1, -1], [0, -1, 0, -1]], interior / 4)  # corners
    assert m.mass.sum() == pytest.approx(0.5)
    # an interior particle carries one cell's area: the sheet's density times spacing²
    assert interior == pytest.approx(0.5 / m.size ** 2 * m.spacing ** 2)


def test_uniform_mass_model_keeps_the_originals_equal_masses():
    m = model_for(resolution=6, mass=0.5, mass_model="uniform")
    np.testing.assert_allclose(m.mass, 0.5 / 36)


def test_masses_by_area_on_the_smallest_sheet():
    m = model_for(resolution=2, mass=0.2)
    np.testing.assert_allclose(m.mass, 0.05)


def test_every_cell_is_split_along_the_same_diagonal():
    n = 5
    tris = grid_triangles(n)
    assert len(tris) == 2 * (n - 1) ** 2
    diagonals = set()
    for i in range(n - 1):
        for j in range(n - 1):
            corners = {i * n + j, i * n + j + 1, (i + 1) * n + j, (i + 1) * n + j + 1}
            halves = [set(t) for t in tris if set(t) <= corners]
            assert len(halves) == 2 and halves[0] | halves[1] == corners
            shared = halves[0] & halves[1]
            diagonals.add(tuple(sorted((a // n - i, a % n - j) for a in shared)))
    assert diagonals == {((0, 1), (1, 0))}  # (i, j+1)–(i+1, j) everywhere
