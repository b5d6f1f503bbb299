"""Self-collision: the spatial hash finds exactly the naive pairs, scales linearly, and keeps
a folded sheet from passing through itself."""


import numpy as np
import pytest


from cloth_tui.sim.collision import selfcollision
from cloth_tui.sim.model import build_model
from cloth_tui.sim.run.runner import Simulation
from ..helpers import scene


def model(n, **overrides):
    s = scene(cloth__resolution=n, **overrides)
    return build_model(s.cloth, s.behavior)


def stencil(n, nz=None):
    """Pairs the constraints govern (skipped by self-collision) on a grid of nz rows of n
    (nz = n: a square), as an (N, N) mask."""
    i, j = np.divmod(np.arange(n * (n if nz is None else nz)), n)
    di = np.abs(i[:, None] - i[None, :])
    dj = np.abs(j[:, None] - j[None, :])
    return ((di <= 1) & (dj <= 1)) | ((di == 0) & (dj == 2)) | ((dj == 0) & (di == 2))


def closest_unrelated(x, n):
    d = np.linalg.norm(x[:, None, :] - x[None, :, :], axis=2)
    d[stencil(n)] = np.inf
    return d.min()


def test_self_collision_joins_the_step_only_when_enabled():
    assert not any("self_collision" in e for e in Simulation(scene()).step.names)
    names = Simulation(scene(behavior__self_collision="hash")).step.names
    assert names.index("self_collision_hash") < names.index("project_constraints")
    assert "self_collision_naive" in Simulation(scene(behavior__self_collision="naive")).step.names


@pytest.mark.parametrize("seed", range(6))
def test_hash_and_naive_resolve_the_same_pairs_on_random_clouds(seed):
    rng = np.random.default_rng(seed)
    n = int(rng.integers(5, 20))
    m = model(n)
    # clouds from sparse to dense, offset so cells straddle negative coordinates
    x = rng.uniform(-0.3, 0.3, (n * n, 3)) * rng.uniform(0.05, 1.0) + rng.normal(0, 2, 3)
    naive = selfcollision.SelfCollision(m, "naive").pair_set(x)
    hashed = selfcollision.SelfCollision(m, "hash").pair_set(x)
    assert naive == hashed
    assert len(naive) > 0 or seed > 3  # the clouds do produce contacts
    # and the pairs are exactly the close, unconstrained ones
    d = np.linalg.norm(x[:, None] - x[None], axis=2)
    close = (d < selfcollision.COLLISION_FRACTION * m.spacing) & ~stencil(n)
    expected = {(int(a), int(b)) for a, b in zip(*np.nonzero(np.triu(close, 1)))}
    assert naive == expected


@pytest.mark.parametrize("shape", [(23, 6), (5, 31), (16, 9)])
def test_hash_and_naive_find_the_brute_force_pairs_on_a_rectangle(shape):
    # Rows of nx particles: the stencil's neighbours (and what is not one, such as the last
    # particle of a row and the first of the next) depend on nx alone, never on nz.
    nx, nz = shape
    m = model([nx, nz], cloth__size=[0.05 * (nx - 1), 0.05 * (nz - 1)])
    assert (m.nx, m.nz) == (nx, nz)
    rng = np.random.default_rng(nx * nz)
    # the sheet crumpled: its particles in a box a few spacings wide, rows wrapped around
    x = m.rest_positions * 0.15 + rng.normal(0, 0.5 * m.spacing, (nx * nz, 3))
    d = np.linalg.norm(x[:, None] - x[None], axis=2)
    close = (d < selfcollision.COLLISION_FRACTION * m.spacing) & ~stencil(nx, nz)
    expected = {(int(a), int(b)) for a, b in zip(*np.nonzero(np.triu(close, 1)))}
    assert len(expected) > 10
    assert selfcollision.SelfCollision(m, "hash").pair_set(x) == expected
    assert selfcollision.SelfCollision(m, "naive").pair_set(x) == expected


def test_pair_buffer_grows_when_a_cloud_has_many_contacts():
    m = model(12)
    x = np.random.default_rng(3).normal(0, 0.01, (144, 3))  # everything in a 1 cm ball
    sc = selfcollision.SelfCollision(m, "hash")
    count = sc.find_pairs(x)
    assert count > 4 * 144 and len(sc.pairs) >= count
    assert sc.pair_set(x) == selfcollision.SelfCollision(m, "naive").pair_set(x)


def test_resolve_pushes_pairs_apart_mass_weighted():
    m = model(4, cloth__pinned="corners", cloth__mass_model="uniform")
    sc = selfcollision.SelfCollision(m, "hash")
    d = sc.distance
    x = np.array(m.rest_positions)
    a, b, pinned = 5, 11, 0  # 5 and 11 are free and unrelated; 0 is a pinned corner
    x[b] = x[a] + [0.0, 0.2 * d, 0.0]
    x[10] = x[pinned] + [0.0, 0.1 * d, 0.0]
    mid = 0.5 * (x[a] + x[b])
    pin0 = x[pinned].copy()
    sc.find_pairs(x)
    selfcollision.resolve_pairs(x, m.inv_mass, sc.pairs, sc.count, d)
    assert np.linalg.norm(x[b] - x[a]) == pytest.approx(d)
    np.testing.assert_allclose(0.5 * (x[a] + x[b]), mid)  # equal masses move equally
    np.testing.assert_array_equal(x[pinned], pin0)  # a pinned particle does not move...
    assert np.linalg.norm(x[10] - x[pinned]) == pytest.approx(d)  # ...the free one does it all


def folded_sheet(method, n=14):
    """A sheet lying on the floor, folded in half: the top half starts one spacing above
    the bottom half, particle over particle, and falls onto it."""
    # no bending constraints: they would unfold the crease before the layers touch
    s = scene(cloth__resolution=n, cloth__pinned="none", cloth__size=0.7, behavior__bending=False,
              behavior__self_collision=method, behavior__substeps=6, scene__friction=0.5)
    sim = Simulation(s)
    m, x = sim.model, sim.state.x
    floor = s.scene.floor_height + s.scene.thickness
    h = m.spacing
    for i in range(n):
        row = slice(i * n, (i + 1) * n)
        mirror = i if i < n // 2 else n - 1 - i
        x[row, 2] = m.rest_positions[mirror * n, 2]
        x[row, 1] = floor if i < n // 2 else floor + h
    sim.state.x_prev[:] = x
    sim._good.restore(sim.state)
    return sim


def test_folded_sheet_does_not_pass_through_itself_with_the_hash():
    n = 14
    sim = folded_sheet("hash", n)
    spacing = sim.model.spacing
    for _ in range(120):
        sim.advance_frame()
    assert closest_unrelated(sim.state.x, n) > spacing / 3
    top = sim.state.x[(n // 2) * n:, 1].mean()
    bottom = sim.state.x[: (n // 2) * n, 1].mean()
    assert top > bottom + 0.5 * spacing  # the top layer still lies on the bottom one
    assert sim.stats().finite
    # control: without self-collision the top layer falls into the bottom one
    off = folded_sheet("off", n)
    for _ in range(120):
        off.advance_frame()
    assert closest_unrelated(off.state.x, n) < spacing / 3


def test_hanging_sheet_piling_on_the_floor_keeps_apart():
    n = 16
    sim = Simulation(scene(cloth__resolution=n, cloth__pinned="one_edge", cloth__height=0.0,
                           behavior__self_collision="hash", behavior__substeps=8))
    for _ in range(150):
        sim.advance_frame()
    assert closest_unrelated(sim.state.x, n) > sim.model.spacing / 3
    assert sim.stats().penetration <= sim.scene.scene.thickness + 1e-3


def sheet_with_contacts(n):
    m = model(n)
    x = np.array(m.rest_positions)
    x += np.random.default_rng(0).normal(0, 0.3 * m.spacing, x.shape)  # some contacts
    return m, x


def folded_cloud(n):
    """A sheet folded onto itself: the far half lies 0.3 spacings above the near half, both
    jittered, so every particle has contacts in the other layer and some in its own."""
    m = model(n)
    x = np.array(m.rest_positions).reshape(n, n, 3)
    x[n // 2:] = x[n // 2 - 1::-1][: n - n // 2] + [0.0, 0.3 * m.spacing, 0.0]
    x += np.random.default_rng(n).normal(0, 0.2 * m.spacing, x.shape)
    return m, x.reshape(-1, 3)


@pytest.mark.parametrize("n", (32, 64, 128))
def test_hash_finds_exactly_the_brute_force_pairs_on_a_folded_sheet(n):
    m, x = folded_cloud(n)
    hashed = selfcollision.SelfCollision(m, "hash").pair_set(x)
    brute = selfcollision.SelfCollision(m, "naive").pair_set(x)  # checked against NumPy above
    assert len(brute) > n * n // 2  # the fold does touch
    assert hashed == brute


def bucket_load(sc):
    """Mean number of particles in the bucket a particle sits in (Σ occupancy² / N), read from
    the table the hash built: what each of a query's 8 lookups has to read, near enough."""
    occupancy = np.diff(sc.cell_start).astype(np.float64)
    return float((occupancy ** 2).sum() / occupancy.sum())


def test_spatial_hash_buckets_stay_small_at_every_size():
    # A hash that folds many cells into few buckets still finds the right pairs, but its
    # work per particle grows with the sheet: O(N²) in disguise.
    load = {}
    for n in (32, 64, 128):
        m, x = sheet_with_contacts(n)
        sc = selfcollision.SelfCollision(m, "hash")
        sc.find_pairs(x)
        load[n] = bucket_load(sc)
    assert max(load.values()) < 1.3 * min(load.values()) and max(load.values()) < 6, load



def test_stencil_constraints_name_the_constraint_of_each_neighbour():
    m = model(7, behavior__shear=False)  # a family off: its columns stay −1
    table = selfcollision.stencil_constraints(m)
    n = m.nx
    for k, (di, dj) in enumerate(selfcollision.STENCIL):
        for p in range(n * n):
            e = table[p, k]
            i, j = divmod(p, n)
            if e < 0:
                on_grid = 0 <= i + di < n and 0 <= j + dj < n
                assert not on_grid or k in (2, 3)  # only the shear family is missing
            else:
                assert sorted(m.edges[e]) == [p, (i + di) * n + j + dj]
    assert (table >= 0).sum() == m.num_constraints  # each constraint once


@pytest.mark.parametrize("method", ["naive", "hash"])
@pytest.mark.parametrize("offset", [(0, 1), (1, 0), (1, 1), (0, 2)])
def test_a_torn_neighbour_pair_collides_and_an_intact_one_does_not(method, offset):
    # The lips of a cut: once the constraint between two neighbours breaks, nothing keeps
    # them apart but self-collision.
    m = model(9)
    n, (di, dj) = m.nx, offset
    a = 4 * n + 4
    b = a + di * n + dj
    x = np.array(m.rest_positions)
    x[b] = x[a] + [0.0, 0.1 * m.spacing, 0.0]  # pressed onto each other
    e = selfcollision.stencil_constraints(m)[a, selfcollision.STENCIL.index(offset)]
    torn = np.ones(m.num_constraints, np.uint8)
    torn[e] = 0
    sc = selfcollision.SelfCollision(m, method)
    assert (a, b) not in sc.pair_set(x)
    assert (a, b) in sc.pair_set(x, torn)

    class State:
        pass
    state = State()
    state.x, state.alive = x.copy(), torn
    sc.apply(state, 0.0)
    assert np.linalg.norm(state.x[b] - state.x[a]) == pytest.approx(sc.distance)
    state.x, state.alive = x.copy(), np.ones(m.num_constraints, np.uint8)
    sc.apply(state, 0.0)
    np.testing.assert_array_equal(state.x[[a, b]], x[[a, b]])  # intact: the constraint's job


@pytest.mark.parametrize("shape, size", [([256, 16], [4.0, 0.235]), ([16, 256], [0.235, 4.0]),
                                         ([512, 8], [8.0, 0.11])])
def test_spatial_hash_buckets_of_a_strip_are_as_small_as_a_squares(shape, size):
    # 4096 particles as a square and as strips both ways: the strips' rows of cells must not
    # fold onto each other in the table.
    square, x = sheet_with_contacts(64)
    sc = selfcollision.SelfCollision(square, "hash")
    sc.find_pairs(x)
    m = model(shape, cloth__size=size)
    y = np.array(m.rest_positions)
    y += np.random.default_rng(0).normal(0, 0.3 * m.spacing, y.shape)
    strip = selfcollision.SelfCollision(m, "hash")
    strip.find_pairs(y)
    assert bucket_load(strip) < 1.15 * bucket_load(sc)
    assert strip.pair_set(y) == selfcollision.SelfCollision(m, "naive").pair_set(y)
