import numpy as np
import pytest

from cloth_tui.scene import Scene
from cloth_tui.sim import grid_sweeps
from cloth_tui.sim.solvers.xpbd import constraints as xpbd
from cloth_tui.sim.model import build_model


def _model(n, families=(True, True, True), pinned="corners", size=1.0):
    """A model of n particles a side, or of shape n = [nx, nz]."""
    s = Scene()
    s.cloth.resolution = n
    s.cloth.size = size
    s.cloth.pinned = pinned
    s.behavior.structural, s.behavior.shear, s.behavior.bending = families
    return build_model(s.cloth, s.behavior)


def _intact(m):
    return np.ones(m.num_constraints, np.uint8)


def _plan(m):
    return grid_sweeps.plan_sweeps(m.nx, m.nz, m.edges, m.color_offsets, m.rest_length,
                                   m.inv_mass)


def _sweep(kernel, m, x, alpha_t, iterations=3, alive=None):
    """The sweeps on x; returns the multipliers λ in model.edges order."""
    lam = np.zeros(m.num_constraints)
    plan = _plan(m)
    alive = _intact(m) if alive is None else alive
    grid_sweeps.sweep(kernel, plan, plan.scratch(), x, alive, lam, alpha_t, iterations)
    return lam


@pytest.mark.parametrize("n", [2, 3, 4, 5, 6, 7, 9, 40, [7, 13], [13, 7], [5, 41], [41, 5],
                               [2, 9], [10, 3]])
@pytest.mark.parametrize("kernel", [grid_sweeps.sweep_grid_colors,
                                    grid_sweeps.sweep_grid_colors_parallel])
@pytest.mark.parametrize("alpha_t", [0.0, 0.5])
def test_sweeps_match_the_plain_loop(n, kernel, alpha_t):
    # Same update, same order inside each colour's conflict-free set: the same positions
    # and (XPBD) multipliers as the loop over model.edges, for every n mod 4, and for
    # sheets whose rows and columns differ in count (and in spacing: a square of 7 × 13).
    m = _model(n, pinned="one_edge")
    rng = np.random.default_rng(m.num_particles)
    x0 = m.rest_positions + rng.normal(scale=0.01, size=m.rest_positions.shape)
    a, b = x0.copy(), x0.copy()
    lam_ref = np.zeros(m.num_constraints)
    xpbd.project_constraints(a, m.inv_mass, m.edges, m.rest_length, _intact(m),
                             m.color_offsets, lam_ref, alpha_t, 3)
    lam = _sweep(kernel, m, b, alpha_t)
    np.testing.assert_allclose(b, a, atol=1e-12)
    if alpha_t:
        np.testing.assert_allclose(lam, lam_ref, atol=1e-12)
    assert np.abs(b - x0).max() > 1e-4


@pytest.mark.parametrize("kernel", [grid_sweeps.sweep_grid_colors,
                                    grid_sweeps.sweep_grid_colors_parallel])
@pytest.mark.parametrize("alpha_t", [0.0, 0.5])
def test_sweeps_skip_torn_constraints_as_the_plain_loop_does(kernel, alpha_t):
    # Tearing (tearing.py) clears alive[e]: the sweeps must leave exactly those constraints
    # out, with their multipliers at zero, as the reference loop does.
    m = _model(13, pinned="one_edge")
    rng = np.random.default_rng(7)
    alive = (rng.random(m.num_constraints) > 0.3).astype(np.uint8)
    x0 = m.rest_positions + rng.normal(scale=0.01, size=m.rest_positions.shape)
    a, b, c = x0.copy(), x0.copy(), x0.copy()
    lam_ref = np.zeros(m.num_constraints)
    xpbd.project_constraints(a, m.inv_mass, m.edges, m.rest_length, alive, m.color_offsets,
                             lam_ref, alpha_t, 3)
    lam = _sweep(kernel, m, b, alpha_t, alive=alive)
    np.testing.assert_allclose(b, a, atol=1e-12)
    assert not lam[alive == 0].any()
    if alpha_t:  # PBD keeps no λ
        np.testing.assert_allclose(lam, lam_ref, atol=1e-12)
    _sweep(kernel, m, c, alpha_t)  # all intact: a different answer, so the mask was read
    assert np.abs(c - b).max() > 1e-4


@pytest.mark.parametrize("kernel", [grid_sweeps.sweep_grid_colors,
                                    grid_sweeps.sweep_grid_colors_parallel])
def test_one_solver_sees_tears_and_undos_between_its_calls(kernel):
    # A solver's scratch keeps `alive` in slot order and takes only what changed: a tear
    # after the first call, and its undo after the second, must both reach the sweeps.
    m = _model(13, pinned="one_edge")
    rng = np.random.default_rng(3)
    x0 = m.rest_positions + rng.normal(scale=0.01, size=m.rest_positions.shape)
    torn = (rng.random(m.num_constraints) > 0.3).astype(np.uint8)
    intact = _intact(m)
    plan = _plan(m)
    scratch = plan.scratch()
    x, ref = x0.copy(), x0.copy()
    lam = np.zeros(m.num_constraints)
    for alive in (intact, torn, intact.copy(), torn.copy()):
        grid_sweeps.sweep(kernel, plan, scratch, x, alive, lam, 0.0, 2)
        xpbd.project_constraints(ref, m.inv_mass, m.edges, m.rest_length, alive,
                                 m.color_offsets, np.zeros(m.num_constraints), 0.0, 2)
        np.testing.assert_allclose(x, ref, atol=1e-12)
        x += rng.normal(scale=0.01, size=x.shape)  # something left for the next call to do
        ref[:] = x


@pytest.mark.parametrize("families", [(True, False, False), (False, True, False),
                                      (False, False, True), (True, False, True)])
def test_sweeps_with_families_switched_off(families):
    m = _model(11, families, pinned="one_edge")
    x0 = m.rest_positions + np.random.default_rng(0).normal(scale=0.01, size=(121, 3))
    a, b = x0.copy(), x0.copy()
    xpbd.project_constraints(a, m.inv_mass, m.edges, m.rest_length, _intact(m),
                             m.color_offsets, np.zeros(m.num_constraints), 0.0, 2)
    _sweep(grid_sweeps.sweep_grid_colors, m, b, 0.0, 2)
    np.testing.assert_allclose(b, a, atol=1e-12)


def test_plan_rejects_colours_out_of_the_sweeps_order():
    # The sweeps visit colours 0…11; a model listing them otherwise would converge to a
    # different answer than its own plain loop.
    m = _model(6)
    off = m.color_offsets
    first, second = slice(off[0], off[1]), slice(off[1], off[2])
    edges = np.concatenate([m.edges[second], m.edges[first], m.edges[off[2]:]])
    offsets = off.copy()
    offsets[1] = off[0] + (off[2] - off[1])
    with pytest.raises(ValueError, match="order"):
        grid_sweeps.plan_sweeps(m.nx, m.nz, edges, offsets, m.rest_length, m.inv_mass)


def test_plan_rejects_a_colour_mixing_two_sweep_colours():
    m = _model(6)
    offsets = np.delete(m.color_offsets, 1)  # colours 0 and 1 as one
    with pytest.raises(ValueError, match="colours"):
        grid_sweeps.plan_sweeps(m.nx, m.nz, m.edges, offsets, m.rest_length, m.inv_mass)


def test_plan_rejects_a_constraint_between_far_particles():
    m = _model(6)
    edges = m.edges.copy()
    edges[0] = (0, 14)
    with pytest.raises(ValueError, match="grid neighbours"):
        grid_sweeps.plan_sweeps(m.nx, m.nz, edges, m.color_offsets, m.rest_length,
                                m.inv_mass)


@pytest.mark.parametrize("n", [2, 3, 5, 8, 13, [7, 13], [13, 7], [5, 41], [3, 2]])
def test_plan_gives_each_constraint_one_slot_joining_its_particles(n):
    # Written apart from the kernels' index arithmetic: every constraint has exactly one
    # slot, whose a and b places in the layout hold that constraint's two particles.
    m = _model(n, pinned="none")
    plan = _plan(m)
    slot_edge = plan.slot_edge
    assert sorted(slot_edge[slot_edge >= 0].tolist()) == list(range(m.num_constraints))
    slots = sorted(s0 + t for _, _, s0, count in plan.chunks for t in range(count))
    assert slots == list(range(plan.slots))  # chunks share no slot and leave none out
    place_of = {int(g): p for p, g in enumerate(plan.grid_offset)}
    for a0, b0, s0, count in plan.chunks:
        for t in range(count):
            e = slot_edge[s0 + t]
            if e >= 0:
                assert (place_of[a0 + t], place_of[b0 + t]) == tuple(m.edges[e])
                assert plan.rest[s0 + t] == m.rest_length[e]


@pytest.mark.parametrize("n", [11, [7, 13], [13, 7], [5, 41]])
def test_plan_colours_touch_each_particle_once(n):
    # Conflict-free even counting the padding and wrapped slots (alive 0) that still write
    # their particles back unchanged: threads sharing a colour then never race.
    plan = _plan(_model(n, pinned="none"))
    for c in range(grid_sweeps.NUM_COLORS):
        places = []
        for a0, b0, _, count in plan.chunks[plan.color_chunks[c]:plan.color_chunks[c + 1]]:
            places += list(range(a0, a0 + count)) + list(range(b0, b0 + count))
        assert len(places) == len(set(places))


def test_crushed_pair_separates_along_its_rest_direction():
    m = _model(3, pinned="none")
    x = np.zeros((9, 3))  # every particle at one point
    _sweep(grid_sweeps.sweep_grid_colors, m, x, 0.0, 1)
    assert np.isfinite(x).all()
    assert np.ptp(x[:, 0]) > 0.1 and np.ptp(x[:, 2]) > 0.1


@pytest.mark.parametrize("kernel", [grid_sweeps.sweep_grid_colors,
                                    grid_sweeps.sweep_grid_colors_parallel])
def test_coincident_ends_move_as_in_the_plain_loop(kernel):
    # Crushed pairs take the loop's pair-dependent direction (a second, scalar pass).
    m = _model(9, pinned="none")
    x0 = m.rest_positions.copy()
    x0[10] = x0[11] = x0[20] = x0[19]  # a horizontal, a vertical and a shear pair crushed
    x0[40:45] = x0[40]
    a, b = x0.copy(), x0.copy()
    xpbd.project_constraints(a, m.inv_mass, m.edges, m.rest_length, _intact(m),
                             m.color_offsets, np.zeros(m.num_constraints), 0.0, 2)
    _sweep(kernel, m, b, 0.0, 2)
    np.testing.assert_allclose(b, a, atol=1e-12)
