"""Physics of the foundation step, on sim/ alone (no GL, no terminal)."""

import numpy as np
import pytest

from cloth_tui.scene import Scene
from cloth_tui.sim.run.runner import Simulation
from .helpers import scene


def test_free_fall_matches_half_g_t_squared():
    s = scene(cloth__pinned="none", behavior__damping=0.0, scene__floor=False,
              cloth__resolution=8)
    sim = Simulation(s)
    y0 = sim.state.x[:, 1].copy()
    for _ in range(60):
        sim.advance_frame()
    t = sim.state.t
    drop = y0 - sim.state.x[:, 1]
    assert t == pytest.approx(1.0)
    np.testing.assert_allclose(drop, 0.5 * 9.81 * t * t, rtol=0.01)


def test_corner_pinned_sheet_rests_with_pins_in_place():
    sim = Simulation(Scene())
    for _ in range(600):
        sim.advance_frame()
    m = sim.model
    np.testing.assert_array_equal(sim.state.x[m.pinned], m.rest_positions[m.pinned])
    assert sim.stats().max_speed < 0.05


def test_more_iterations_give_less_stretch():
    results = []
    for k in (1, 4, 16):
        sim = Simulation(scene(behavior__iterations=k, behavior__substeps=1,
                               behavior__adaptive=False, behavior__tethers=False))
        for _ in range(120):
            sim.advance_frame()
        results.append(sim.stats().mean_stretch)
    assert results[0] > results[1] > results[2]


def test_no_particle_below_floor():
    sim = Simulation(scene(cloth__pinned="none", cloth__height=2.0))
    for _ in range(240):
        sim.advance_frame()
        assert sim.state.x[:, 1].min() >= sim.scene.scene.floor_height
    assert sim.stats().penetration == 0.0


def test_pipeline_lists_only_enabled_effects():
    on = Simulation(Scene()).step.names
    assert "gravity" in on and "collide_floor" in on
    off = Simulation(scene(forces__gravity=False, scene__floor=False)).step.names
    assert "gravity" not in off and "collide_floor" not in off
    assert "apply_pins" not in Simulation(scene(cloth__pinned="none")).step.names


def test_integrate_off_freezes_the_sheet():
    sim = Simulation(scene(forces__integrate=False))
    x0 = sim.state.x.copy()
    sim.advance_frame()
    np.testing.assert_array_equal(sim.state.x, x0)


def test_bump_moves_particle_and_neighbours_less():
    sim = Simulation(scene(cloth__resolution=11))
    c = 5 * 11 + 5
    x0 = sim.state.x.copy()
    sim.bump(c, (0.0, 0.1, 0.0))
    dy = sim.state.x[:, 1] - x0[:, 1]
    assert dy[c] == pytest.approx(0.1)
    assert 0 < dy[c + 1] < dy[c]
    assert dy[c + 3] < dy[c + 1]
    assert np.all(dy[sim.model.pinned] == 0)


def test_reset_restores_rest_state():
    sim = Simulation(Scene())
    for _ in range(10):
        sim.advance_frame()
    sim.reset()
    np.testing.assert_array_equal(sim.state.x, sim.model.rest_positions)
    assert sim.state.t == 0.0


def test_set_scene_rebuilds_model_only_when_needed():
    sim = Simulation(Scene())
    model = sim.model
    assert sim.set_scene(sim.scene.with_value("forces.gravity", False)) is False
    assert sim.model is model and "gravity" not in sim.step.names
    assert sim.set_scene(sim.scene.with_value("cloth.resolution", 10)) is True
    assert (sim.model.nx, sim.model.nz) == (10, 10)


def test_diverging_step_is_recovered():
    sim = Simulation(Scene())
    sim.advance_frame()
    sim.state.x[3] = np.nan  # a blow-up as a solver would produce it
    sim.state.v[3] = np.nan
    sim.advance_frame()
    assert sim.state.is_finite()
    assert sim.recoveries >= 1


def test_tethers_bound_distance_to_nearest_pin_and_cut_stretch():
    # pbd, whose one pass a substep leaves a 48² sheet sagging far from its pins (hpbd's
    # coarse levels take out most of that stretch themselves)
    fixed = dict(cloth__resolution=48, behavior__substeps=1, behavior__adaptive=False,
                 behavior__solver="pbd")
    plain = Simulation(scene(**fixed, behavior__tethers=False))
    tethered = Simulation(scene(**fixed, behavior__tethers=True))
    assert "enforce_tethers" in tethered.step.names and "enforce_tethers" not in plain.step.names
    for _ in range(200):
        plain.advance_frame()
        tethered.advance_frame()
    m, x = tethered.model, tethered.state.x
    free = m.tether_pin >= 0
    d = np.linalg.norm(x[free] - x[m.pinned[m.tether_pin[free]]], axis=1)
    # The constraints run after the tethers, so a tether may be exceeded a little, never by
    # more than two grid spacings (untethered, the sheet sags many spacings from its pins).
    assert np.all(d <= m.tether_length[free] + 2 * m.spacing)
    assert tethered.stats().max_stretch < 0.5 * plain.stats().max_stretch
