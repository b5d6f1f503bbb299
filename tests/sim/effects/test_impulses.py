"""Rain: drops displace particles downward with falloff, reproducibly from the seed."""

import numpy as np
import pytest


from cloth_tui.sim.effects import impulses
from cloth_tui.sim.model import build_model
from cloth_tui.sim.params import StepParams
from cloth_tui.sim.run.runner import Simulation
from cloth_tui.sim.state import ClothState
from ..helpers import scene


def rainy(**overrides):
    kw = dict(cloth__resolution=12, forces__rain=True, forces__rain_rate=30.0,
              forces__rain_strength=0.02)
    return scene(**{**kw, **overrides})


def test_rain_joins_the_frame_only_when_enabled():
    assert "rain" not in Simulation(scene()).step.names
    assert Simulation(rainy()).step.names[0] == "rain"  # a frame effect, before the substeps
    assert "rain" not in Simulation(rainy(forces__rain_rate=0.0)).step.names


def test_a_drop_pushes_its_particle_down_and_neighbours_less():
    s = scene(cloth__resolution=11, cloth__pinned="corners")
    m = build_model(s.cloth, s.behavior)
    st = ClothState.from_model(m)
    n, c, depth, dt = 11, 5 * 11 + 5, 0.02, 1 / 60
    impulses.apply_raindrop(st.x, st.v, m.inv_mass, n, n, c, depth, 1 / dt,
                            1 / impulses.RAIN_RADIUS ** 2, impulses.RAIN_REACH)
    dy = st.x[:, 1] - m.rest_positions[:, 1]
    assert dy[c] == pytest.approx(-depth)
    ring = [dy[c + 1], dy[c + n + 1], dy[c + 2], dy[c + 3]]  # 1, √2, 2, 3 spacings away
    assert all(a < b < 0 for a, b in zip([dy[c]] + ring, ring))  # less and less, all down
    assert dy[c + 1] == pytest.approx(-depth * np.exp(-1 / impulses.RAIN_RADIUS ** 2))
    assert dy[c + 4] == 0.0  # beyond the reach
    assert np.all(st.x[:, [0, 2]] == m.rest_positions[:, [0, 2]])  # straight down
    np.testing.assert_allclose(st.v[:, 1], dy / dt)  # the velocity of that motion
    # pinned particles are never moved
    impulses.apply_raindrop(st.x, st.v, m.inv_mass, n, n, 0, depth, 1 / dt,
                            1 / impulses.RAIN_RADIUS ** 2, impulses.RAIN_REACH)
    assert st.x[0, 1] == m.rest_positions[0, 1]


def test_a_drop_on_a_rectangle_stays_within_its_row_ends():
    # 9 particles a row, 4 rows: a drop at the end of row 1 moves particles of rows 0–3 near
    # column 8, and nothing at the start of the next row (the index after it).
    s = scene(cloth__resolution=[9, 4], cloth__size=[2.0, 0.75], cloth__pinned="none")
    m = build_model(s.cloth, s.behavior)
    st = ClothState.from_model(m)
    c, depth = 1 * 9 + 8, 0.02
    impulses.apply_raindrop(st.x, st.v, m.inv_mass, m.nx, m.nz, c, depth, 60.0,
                            1 / impulses.RAIN_RADIUS ** 2, impulses.RAIN_REACH)
    moved = np.flatnonzero(st.x[:, 1] != m.rest_positions[:, 1])
    rows, cols = np.divmod(moved, m.nx)
    assert set(rows.tolist()) == {0, 1, 2, 3} and cols.min() == 8 - impulses.RAIN_REACH
    assert st.x[c, 1] == pytest.approx(m.rest_positions[c, 1] - depth)


def positions_after(s, frames=30):
    sim = Simulation(s)
    for _ in range(frames):
        sim.advance_frame()
    return sim.state.x.copy(), sim


def test_rain_is_reproducible_from_the_seed():
    # no gravity, edges held: only the rain moves the sheet
    calm = dict(forces__gravity=False, cloth__pinned="four_edges")
    a, sim = positions_after(rainy(behavior__seed=7, **calm))
    b, _ = positions_after(rainy(behavior__seed=7, **calm))
    c, _ = positions_after(rainy(behavior__seed=8, **calm))
    np.testing.assert_array_equal(a, b)
    assert np.abs(a - c).max() > 1e-3
    y0 = sim.model.rest_positions[0, 1]
    assert np.abs(a[:, 1] - y0).max() > 1e-3  # the drops moved the sheet off its plane
    assert sim.step.frame_effects[0].drops > 5
    assert sim.stats().finite


def test_drop_count_is_poisson_with_the_rate():
    s = rainy(forces__rain_rate=20.0)
    model = build_model(s.cloth, s.behavior)
    rain = impulses.build_impulses(s, model, StepParams.of(s))[0]
    dt = 1 / 60
    counts = np.array([len(rain.strikes(k * dt, dt)) for k in range(3000)])  # 50 s
    assert counts.sum() == pytest.approx(20.0 * 50, rel=0.1)  # σ ≈ 3 %
    assert counts.var() == pytest.approx(counts.mean(), rel=0.25)  # Poisson: var = mean
    # the same frame always gets the same drops
    np.testing.assert_array_equal(rain.strikes(1.0, dt), rain.strikes(1.0, dt))
