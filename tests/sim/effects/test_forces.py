"""Forces: wind, custom fields, wave. Each test checks the physics, not only that it runs."""

import math

import numpy as np
import pytest

from cloth_tui.scene import Scene
from cloth_tui.sim.effects import forces
from cloth_tui.sim.model import build_model
from cloth_tui.sim.params import StepParams
from cloth_tui.sim.run.runner import Simulation
from cloth_tui.sim.state import ClothState
from ..helpers import run, scene


def model_and_state(**overrides):
    s = scene(**overrides)
    m = build_model(s.cloth, s.behavior)
    return s, m, ClothState.from_model(m)


def total_force(model, accel):
    return (model.mass[:, None] * accel).sum(axis=0)


# -- wind -----------------------------------------------------------------------------------
def test_wind_joins_the_step_only_when_enabled():
    assert "wind" not in Simulation(scene()).step.names
    assert "wind" in Simulation(scene(forces__wind=True)).step.names
    assert "wind" not in Simulation(scene(forces__wind=True, forces__wind_strength=0.0)).step.names


def test_wind_on_a_flat_sheet_is_drag_times_area_along_the_normal():
    # A 1 m² horizontal sheet in an updraft of 5 m/s: F = ½ρC·A·v² upward.
    s, m, st = model_and_state(cloth__resolution=9, cloth__pinned="none",
                               forces__wind_direction=[0.0, 1.0, 0.0])
    wind = forces.Wind(m, StepParams(wind_speed=5.0, wind_direction=[0.0, 1.0, 0.0]))
    out = np.zeros_like(st.x)
    wind.accumulate(st.x, st.v, 0.0, out)
    expected = 0.5 * forces.AIR_DENSITY * forces.DRAG_COEFFICIENT * 1.0 * 25.0
    np.testing.assert_allclose(total_force(m, out), [0.0, expected, 0.0], atol=1e-9 * expected)
    # twice the side → four times the area → four times the force
    _, m2, st2 = model_and_state(cloth__resolution=9, cloth__pinned="none", cloth__size=2.0)
    out2 = np.zeros_like(st2.x)
    up = StepParams(wind_speed=5.0, wind_direction=[0.0, 1.0, 0.0])
    forces.Wind(m2, up).accumulate(st2.x, st2.v, 0.0, out2)
    assert total_force(m2, out2)[1] == pytest.approx(4 * expected)


def test_wind_scales_with_angle_and_vanishes_edge_on():
    _, m, st = model_and_state(cloth__resolution=5, cloth__pinned="none")
    f = {}
    for deg in (0.0, 60.0, 90.0):
        a = math.radians(deg)  # angle between the air and the sheet's normal (y)
        out = np.zeros_like(st.x)
        air = StepParams(wind_speed=5.0, wind_direction=[math.sin(a), math.cos(a), 0.0])
        forces.Wind(m, air).accumulate(st.x, st.v, 0.0, out)
        f[deg] = total_force(m, out)
    assert f[60.0][1] == pytest.approx(0.25 * f[0.0][1])  # ∝ cos²
    assert np.abs(f[90.0]).max() < 1e-12
    assert abs(f[60.0][0]) < 1e-12  # pressure acts along the normal only


def test_sheet_moving_with_the_air_feels_no_wind():
    _, m, st = model_and_state(cloth__resolution=7, cloth__pinned="none")
    air = np.array([0.0, 3.0, 4.0])
    wind = forces.Wind(m, StepParams(wind_speed=5.0, wind_direction=air))
    still, moving = np.zeros_like(st.x), np.zeros_like(st.x)
    wind.accumulate(st.x, np.zeros_like(st.v), 0.0, still)
    wind.accumulate(st.x, np.tile(air, (m.num_particles, 1)), 0.0, moving)
    assert np.abs(still).max() > 1.0
    assert np.abs(moving).max() < 1e-9


def test_wind_blows_a_flag_downwind():
    base = dict(cloth__resolution=12, cloth__pinned="one_edge", cloth__height=0.6,
                behavior__substeps=6)
    calm = run(Simulation(scene(**base)), 90)
    windy = run(Simulation(scene(**base, forces__wind=True, forces__wind_strength=4.0)), 90)
    z_calm, z_windy = calm.state.x[:, 2].mean(), windy.state.x[:, 2].mean()
    assert z_windy > z_calm + 0.2  # the free edge is carried along +z
    assert windy.stats().finite and windy.stats().max_stretch < 0.1


def test_gusty_wind_varies_in_time_and_constant_does_not():
    assert forces.wind_speed(5.0, "constant", 0.7) == 5.0
    quarter = forces.GUST_PERIOD / 4
    assert forces.wind_speed(5.0, "gusty", quarter) == pytest.approx(7.5)
    assert forces.wind_speed(5.0, "gusty", 3 * quarter) == pytest.approx(2.5)


# -- custom fields --------------------------------------------------------------------------
def free_floating(**overrides):
    return scene(cloth__resolution=12, cloth__pinned="none", forces__gravity=False,
                 scene__floor=False, **overrides)


def spread(x):
    """Radius of the smallest centroid-centred ball holding the sheet, and the RMS radius."""
    r = np.linalg.norm(x - x.mean(axis=0), axis=1)
    return r.max(), np.sqrt(np.mean(r * r))


def test_black_hole_pulls_the_sheet_together():
    sim = Simulation(free_floating(forces__custom="black_hole", forces__custom_strength=10.0))
    assert "black_hole" in sim.step.names
    centre = np.array(forces.FIELD_CENTER)
    (r_max0, r_rms0), d0 = spread(sim.state.x), np.linalg.norm(sim.state.x - centre, axis=1)
    run(sim, 150)
    (r_max, r_rms), d = spread(sim.state.x), np.linalg.norm(sim.state.x - centre, axis=1)
    # Gathered together (an inextensible sheet cannot shrink its corners' reach much, but
    # its mass gathers)...
    assert r_rms < 0.9 * r_rms0 and r_max < 1.05 * r_max0
    # ...around the centre (to 0.71 of the start with hpbd, 0.66 with pbd, whose sheet
    # stretches toward the centre a little more)
    assert d.mean() < 0.75 * d0.mean()
    assert sim.state.is_finite()
    idle = run(Simulation(free_floating()), 150)  # control: nothing pulls, nothing shrinks
    assert spread(idle.state.x) == pytest.approx((r_max0, r_rms0))


def test_black_hole_is_finite_at_its_centre_and_falls_off_with_distance():
    _, m, _ = model_and_state(cloth__resolution=2, cloth__pinned="none")
    hole = StepParams(custom_strength=10.0, custom_rate=0.0)
    field = forces.CustomField(m, "black_hole", hole)
    c = np.array(forces.FIELD_CENTER)
    x = np.array([c, c + [0.01, 0, 0], c + [0.5, 0, 0], c + [2.0, 0, 0]])
    out = np.zeros_like(x)
    field.accumulate(x, np.zeros_like(x), 0.0, out)
    mag = np.linalg.norm(out, axis=1)
    assert mag[0] == 0.0 and np.all(np.isfinite(mag))
    assert out[2, 0] < 0  # toward the centre
    assert mag[2] == pytest.approx(10.0, rel=0.1)  # ≈ strength at the reference radius
    eps, L = forces.SOFTENING, forces.REFERENCE_RADIUS
    expected = [10.0 * L * L * r / (r * r + eps * eps) ** 1.5 for r in (0.01, 0.5, 2.0)]
    np.testing.assert_allclose(mag[1:], expected, rtol=1e-9)  # the documented formula
    assert mag[3] == pytest.approx(mag[2] / 16, rel=0.1)  # ~inverse square far away


def test_anti_gravity_lifts_and_custom_rate_varies_it():
    sim = run(Simulation(free_floating(forces__custom="anti_gravity",
                                       forces__custom_rate=0.0)), 30)
    assert sim.state.x[:, 1].mean() > Scene().cloth.height + 0.1
    _, m, st = model_and_state(cloth__resolution=2, cloth__pinned="none")
    lift = StepParams(custom_strength=10.0, custom_rate=1.0)
    field = forces.CustomField(m, "anti_gravity", lift)
    lifts = []
    for t in (0.25, 0.75):
        out = np.zeros_like(st.x)
        field.accumulate(st.x, st.v, t, out)
        lifts.append(out[0, 1])
    assert lifts == pytest.approx([10.0, 0.0], abs=1e-9)


def test_vortex_spins_the_sheet_about_the_vertical_axis():
    sim = run(Simulation(free_floating(forces__custom="vortex", forces__custom_rate=0.0)), 30)
    x, v = sim.state.x, sim.state.v
    l_y = np.sum(x[:, 2] * v[:, 0] - x[:, 0] * v[:, 2])  # (x × v)_y
    assert l_y < -0.1  # a ∝ (−z, 0, x) turns +x toward +z: angular momentum along −y
    assert abs(v[:, 1]).max() < 1e-9  # a horizontal swirl


def test_tractor_beam_lifts_only_under_the_beam():
    _, m, st = model_and_state(cloth__resolution=21, cloth__pinned="none")
    out = np.zeros_like(st.x)
    beam = StepParams(custom_strength=10.0, custom_rate=0.0)
    forces.CustomField(m, "tractor_beam", beam).accumulate(st.x, st.v, 0.0, out)
    under = np.linalg.norm(st.x[:, [0, 2]] - [forces.BEAM_ORBIT, 0.0], axis=1)
    assert out[np.argmin(under), 1] == pytest.approx(10.0, rel=0.02)
    assert out[np.argmax(under), 1] < 0.01
    assert np.abs(out[:, [0, 2]]).max() == 0.0


@pytest.mark.parametrize("kind", ["black_hole", "vortex", "anti_gravity", "tractor_beam"])
def test_apply_is_accumulate_at_the_state(kind):
    s, m, st = model_and_state(cloth__resolution=6, cloth__pinned="corners")
    st.t = 0.3
    st.x += np.random.default_rng(1).normal(0, 0.05, st.x.shape)
    effect = forces.CustomField(m, kind, StepParams(custom_strength=7.0, custom_rate=0.5))
    out = np.zeros_like(st.x)
    effect.accumulate(st.x, st.v, st.t, out)
    effect.apply(st, 0.01)
    np.testing.assert_array_equal(st.accel, out)
    assert np.all(st.accel[m.pinned] == 0.0)  # pinned particles are not accelerated


# -- wave -----------------------------------------------------------------------------------
def test_wave_drives_one_edge_and_holds_the_other():
    s = scene(cloth__resolution=10, cloth__pinned="none", behavior__wave=True,
              behavior__wave_amplitude=0.1, behavior__wave_frequency=1.0)
    sim = Simulation(s)
    driven, held = forces.wave_rows(10, 10)
    assert set(driven) | set(held) <= set(sim.model.pinned)
    assert "wave" in sim.step.names
    y0 = sim.model.rest_positions[0, 1]
    run(sim, 15)  # t = 0.25 s: a quarter period, the crest
    assert sim.state.t == pytest.approx(0.25)
    np.testing.assert_allclose(sim.state.x[driven, 1], y0 + 0.1, atol=1e-12)
    np.testing.assert_allclose(sim.state.x[held, 1], y0, atol=1e-12)
    run(sim, 30)  # t = 0.75 s: the trough
    np.testing.assert_allclose(sim.state.x[driven, 1], y0 - 0.1, atol=1e-12)
    assert "wave" not in Simulation(scene()).step.names
