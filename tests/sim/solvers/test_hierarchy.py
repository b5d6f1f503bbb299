"""The coarse levels of hierarchical PBD: what they span, weigh and leave out."""

import numpy as np
import pytest

from cloth_tui.sim.solvers.hpbd.level_grids import axis_nodes, build_levels, torn_flags
from cloth_tui.sim.model import build_model
from cloth_tui.sim.effects.tearing import cut_between
from cloth_tui.sim.state import ClothState

from ..helpers import scene


def model_of(**overrides):
    sc = scene(**overrides)
    return build_model(sc.cloth, sc.behavior, sc.pins)


def test_axis_nodes_keep_both_ends():
    assert axis_nodes(10, 4).tolist() == [0, 4, 5, 9]  # symmetric, the odd interval mid-way
    assert axis_nodes(9, 4).tolist() == [0, 4, 8]
    assert axis_nodes(26, 2).tolist() == [0, 2, 4, 6, 8, 10, 12, 13, 15, 17, 19, 21, 23, 25]
    for count in range(3, 70):
        for step in (2, 4, 8):
            nodes = axis_nodes(count, step)
            assert nodes.tolist() == sorted(count - 1 - nodes)  # symmetric
            assert set(nodes) <= set(axis_nodes(count, step // 2 or 1))  # nested


@pytest.mark.parametrize("n", [9, 24, 33])
def test_levels_nest_down_to_three_or_four_nodes_a_side(n):
    m = model_of(cloth__resolution=n)
    levels = build_levels(m)
    sizes = [len(lv.nodes) for lv in levels]
    assert sizes == sorted(sizes)  # coarsest first: 3 × 3, or 4 × 4 where the middle is no node
    assert levels[0].nz == levels[0].nx and levels[0].nz in (3, 4)
    finest = levels[-1]
    assert len(finest.sources) == m.num_particles
    for coarse, fine in zip(levels, levels[1:]):
        assert len(coarse.sources) == len(fine.nodes)
        assert set(coarse.nodes.tolist()) <= set(fine.nodes.tolist())
    for lv in levels:
        # every finer particle is a convex combination of its level's nodes
        assert np.allclose(lv.weights.sum(axis=1), 1.0)
        assert (lv.weights >= 0).all() and (lv.sources < len(lv.nodes)).all()


def test_a_level_weighs_the_whole_sheet_and_pins_its_corners():
    m = model_of(cloth__resolution=20, cloth__pinned="corners")
    for lv in build_levels(m):
        assert 1.0 / lv.inv_mass[lv.inv_mass > 0].min() > 0
        pinned = lv.inv_mass == 0
        assert sorted(lv.nodes[pinned].tolist()) == sorted(m.pinned.tolist())


def test_coarse_constraints_are_at_rest_on_the_flat_sheet():
    """Restricting the flat sheet gives each coarse pair its rest length: a sheet at rest has
    nothing for a coarse level to correct."""
    from cloth_tui.sim.solvers.hpbd.position_levels import ProjectHierarchy

    m = model_of(cloth__resolution=21, cloth__pinned="one_edge")
    st = ClothState.from_model(m)
    before = st.x.copy()
    ProjectHierarchy(m).apply(st, 1e-3)
    assert np.abs(st.x - before).max() < 1e-12


def test_no_levels_without_stretch_or_shear_constraints():
    m = model_of(cloth__resolution=16, behavior__structural=False, behavior__shear=False)
    assert build_levels(m) == []


def test_a_cut_leaves_out_every_coarse_constraint_across_it():
    """A cut across the middle row: no coarse constraint or interpolation cell left in use
    joins the two halves."""
    m = model_of(cloth__resolution=24, behavior__tear=True)
    st = ClothState.from_model(m)
    row = 12
    assert cut_between(m, st, row * m.nx, row * m.nx + m.nx - 1) > 0
    for lv in build_levels(m):
        alive = torn_flags(m, st.alive, lv.edge_box).astype(bool)
        r0, r1 = lv.edge_box[:, 0], lv.edge_box[:, 1]
        across = (r0 <= row) & (r1 >= row + 1)
        assert across.any() and not alive[across].any()
        assert alive.any()  # the halves keep their own
        cells = torn_flags(m, st.alive, lv.target_box).astype(bool)
        c0, c1 = lv.target_box[:, 0], lv.target_box[:, 1]
        assert not cells[(c0 <= row) & (c1 >= row + 1)].any()
    st.alive[:] = 1
    for lv in build_levels(m):
        assert torn_flags(m, st.alive, lv.edge_box).all()
