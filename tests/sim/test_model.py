import numpy as np
import pytest

from cloth_tui.scene import Scene
from cloth_tui.sim.model import (BENDING, MODEL_KEYS, SHEAR, STRUCTURAL, build_model,
                                 grid_triangles, pinned_indices)


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


@pytest.mark.parametrize("nx, nz", [(5, 5), (7, 4), (3, 9)])
def test_pin_modes_pin_documented_particles(nx, nz):
    idx = np.arange(nx * nz).reshape(nz, nx)  # rows of nx particles
    assert set(pinned_indices(nx, nz, "none")) == set()
    assert set(pinned_indices(nx, nz, "corners")) == {0, nx - 1, nx * (nz - 1), nx * nz - 1}
    assert set(pinned_indices(nx, nz, "one_edge")) == set(range(nx))  # row 0
    assert set(pinned_indices(nx, nz, "two_edges")) == set(idx[0]) | set(idx[-1])
    border = set(idx[0]) | set(idx[-1]) | set(idx[:, 0]) | set(idx[:, -1])
    assert set(pinned_indices(nx, nz, "four_edges")) == border
    assert len(border) == 2 * (nx + nz) - 4


def test_random_pins_depend_on_the_seed_alone():
    r1 = pinned_indices(20, 20, "random", seed=3, fraction=0.1)
    assert len(r1) == 40
    np.testing.assert_array_equal(r1, pinned_indices(20, 20, "random", seed=3, fraction=0.1))
    assert not np.array_equal(r1, pinned_indices(20, 20, "random", seed=4, fraction=0.1))
    assert len(pinned_indices(30, 10, "random", seed=3, fraction=0.1)) == 30


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
    assert interior == pytest.approx(0.5 / m.width / m.length * m.spacing_x * m.spacing_z)


def test_masses_by_area_on_a_rectangle():
    # 2 m × 0.5 m at 9 × 4 particles: x spacing 0.25 m, z spacing 1/6 m; every cell alike.
    m = model_for(size=[2.0, 0.5], resolution=[9, 4], mass=0.6)
    grid = m.mass.reshape(m.shape)
    assert grid.shape == (4, 9)
    interior = 0.6 / (2.0 * 0.5) * 0.25 * (0.5 / 3)  # density × one cell's area
    np.testing.assert_allclose(grid[1:-1, 1:-1], interior)
    np.testing.assert_allclose(grid[0, 1:-1], interior / 2)
    np.testing.assert_allclose(grid[1:-1, 0], interior / 2)
    np.testing.assert_allclose(grid[[0, 0, -1, -1], [0, -1, 0, -1]], interior / 4)
    assert m.mass.sum() == pytest.approx(0.6)


def test_a_rectangle_is_rows_of_nx_particles_x_with_the_column():
    m = model_for(size=[2.0, 0.5], resolution=[9, 4], height=0.3)
    assert (m.nx, m.nz, m.width, m.length, m.num_particles) == (9, 4, 2.0, 0.5, 36)
    grid = m.rest_positions.reshape(m.shape + (3,))
    np.testing.assert_allclose(grid[0, :, 0], np.linspace(-1.0, 1.0, 9))  # x along a row
    np.testing.assert_allclose(grid[:, 0, 2], np.linspace(-0.25, 0.25, 4))  # z down a column
    np.testing.assert_allclose(grid[..., 1], 0.3)
    assert m.spacing_x == pytest.approx(0.25) and m.spacing_z == pytest.approx(0.5 / 3)
    assert m.spacing == m.spacing_z and m.extent == 2.0


def test_constraint_counts_on_a_rectangle():
    nx, nz = 9, 4
    m = model_for(size=[2.0, 0.5], resolution=[nx, nz])
    counts = np.bincount(m.family, minlength=3)
    assert counts[STRUCTURAL] == nz * (nx - 1) + nx * (nz - 1)
    assert counts[SHEAR] == 2 * (nx - 1) * (nz - 1)
    assert counts[BENDING] == nz * (nx - 2) + nx * (nz - 2)
    a, b = m.edges[:, 0], m.edges[:, 1]
    di, dj = b // nx - a // nx, b % nx - a % nx
    hx, hz = m.spacing_x, m.spacing_z
    expect = np.hypot(di * hz, dj * hx)  # rest lengths from the two spacings
    np.testing.assert_allclose(m.rest_length, expect)
    assert len(m.triangles) == 2 * (nx - 1) * (nz - 1)
    assert len(np.unique(m.triangles)) == nx * nz


def test_tethers_on_a_rectangle_reach_the_nearest_pin():
    m = model_for(size=[3.0, 1.0], resolution=[13, 5], pinned="one_edge")
    pins = m.rest_positions[m.pinned]
    free = np.setdiff1d(np.arange(m.num_particles), m.pinned)
    d = np.linalg.norm(m.rest_positions[free, None] - pins[None], axis=2).min(axis=1)
    np.testing.assert_allclose(m.tether_length[free], d)
    assert m.tether_length[free].max() == pytest.approx(1.0)  # the far row, a length away


def test_uniform_mass_model_keeps_the_originals_equal_masses():
    m = model_for(resolution=6, mass=0.5, mass_model="uniform")
    np.testing.assert_allclose(m.mass, 0.5 / 36)


def test_masses_by_area_on_the_smallest_sheet():
    m = model_for(resolution=2, mass=0.2)
    np.testing.assert_allclose(m.mass, 0.05)


@pytest.mark.parametrize("nx, nz", [(5, 5), (6, 3), (3, 6)])
def test_every_cell_is_split_along_the_same_diagonal(nx, nz):
    tris = grid_triangles(nx, nz)
    assert len(tris) == 2 * (nx - 1) * (nz - 1)
    diagonals = set()
    for i in range(nz - 1):
        for j in range(nx - 1):
            corners = {i * nx + j, i * nx + j + 1, (i + 1) * nx + j, (i + 1) * nx + j + 1}
            halves = [set(t) for t in tris if set(t) <= corners]
            assert len(halves) == 2 and halves[0] | halves[1] == corners
            shared = halves[0] & halves[1]
            diagonals.add(tuple(sorted((a // nx - i, a % nx - j) for a in shared)))
    assert diagonals == {((0, 1), (1, 0))}  # (i, j+1)–(i+1, j) everywhere


class ReadRecorder:
    """Stands for a scene section and records each of its keys read, through its methods
    and properties too (they run with the recorder as self)."""

    def __init__(self, section, name: str, read: set):
        object.__setattr__(self, "_real", section)
        object.__setattr__(self, "_name", name)
        object.__setattr__(self, "_read", read)

    def __getattr__(self, key):
        attr = getattr(type(self._real), key, None)
        if isinstance(attr, property):
            return attr.fget(self)
        if callable(attr):
            return attr.__get__(self)
        self._read.add((self._name, key))
        return getattr(self._real, key)


def keys_build_model_reads(scene: Scene) -> set:
    from cloth_tui.sim.run.rebuild_policy import scene_material

    read: set = set()
    build_model(ReadRecorder(scene.cloth, "cloth", read),
                ReadRecorder(scene.behavior, "behavior", read), scene.pins,
                scene_material(scene))
    return read


def test_the_model_keys_are_the_keys_build_model_reads():
    """What rebuilds the sheet is what the sheet is built from: a key build_model reads and
    MODEL_KEYS misses would change nothing on screen until a restart; a key in MODEL_KEYS
    that it does not read would rebuild the sheet for nothing."""
    fabric = Scene().with_values({"material": {"preset": "denim"}})
    # the original's keys (cloth.mass) and a fabric's (its density instead) between them
    read = keys_build_model_reads(Scene()) | keys_build_model_reads(fabric)
    # whether tethers are built: needs_new_model compares uses_tethers itself
    tether_only = {("behavior", "solver"), ("behavior", "tear")}
    assert read - tether_only == MODEL_KEYS
