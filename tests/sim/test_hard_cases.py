"""Scenes that try to break the solver. Each would fail if the step blew up."""

import numpy as np
import pytest

from cloth_tui.scene import PIN_MODES

from .hardcase import run_hard


def test_very_large_timestep():
    # 5 frames per second and one substep: 0.2 s steps, 11× the original's.
    run_hard({"behavior.frame_rate": 5.0, "behavior.substeps": 1, "cloth.pinned": "none",
              "cloth.height": 3.0}, min_steps=2000, max_stretch=0.6)


@pytest.mark.parametrize("n", [2, 3])
def test_tiniest_sheets(n):
    run_hard({"cloth.resolution": n, "cloth.pinned": "none"})
    run_hard({"cloth.resolution": n, "cloth.pinned": "corners"})


@pytest.mark.slow
def test_large_sheet():
    run_hard({"cloth.resolution": 200, "behavior.tethers": True}, min_steps=2000)


def test_large_sheet_short():
    # Without tethers a corner-pinned 128² sheet at 4 iterations stretches several-fold next
    # to the pins (PBD converges slowly over long distances): tethers bound it.
    run_hard({"cloth.resolution": 128, "behavior.tethers": True},
             min_steps=800)


def test_all_constraint_families_off():
    sim = run_hard({"behavior.structural": False, "behavior.shear": False,
                    "behavior.bending": False})
    # Nothing holds the particles: they fall to the floor and stay there.
    assert sim.state.x[:, 1][sim.model.inv_mass > 0].max() < -0.45


def test_zero_damping():
    run_hard({"behavior.damping": 0.0})


@pytest.mark.parametrize("mass", [1e-6, 1e6])
def test_extreme_masses(mass):
    run_hard({"cloth.mass": mass})


@pytest.mark.parametrize("mode", PIN_MODES)
def test_every_pin_mode(mode):
    sim = run_hard({"cloth.pinned": mode, "cloth.resolution": 20}, min_steps=2000)
    m = sim.model
    np.testing.assert_array_equal(sim.state.x[m.pinned], m.rest_positions[m.pinned])


def test_coincident_particles():
    def crush(sim, frame):
        if frame == 0:
            sim.state.x[:] = sim.state.x[0]  # every particle at one point
    # The sheet unfolds from a point into a tangle: some constraints stay stretched where
    # folds lock them, so the bound is loose, but nothing runs away.
    sim = run_hard({"cloth.pinned": "none", "cloth.resolution": 10}, on_frame=crush,
                   max_stretch=1.5)
    assert sim.stats()["mean_stretch"] < 0.1
    assert np.ptp(sim.state.x[:, 0]) > 0.3  # it did spread out


def test_drop_from_several_metres_onto_floor():
    run_hard({"cloth.pinned": "none", "cloth.height": 8.0})


def test_strong_gravity():
    run_hard({"forces.gravity_strength": 1000.0, "cloth.pinned": "one_edge"},
             max_stretch=1.0)


INTEGRATORS = ["explicit_euler", "symplectic_euler", "verlet", "midpoint", "rk4",
               "implicit_euler"]


@pytest.mark.parametrize("integrator", INTEGRATORS)
def test_stiff_springs_with_every_integrator(integrator):
    # k = 1e5 N/m on 1.4 g particles: explicit methods are far past their stable step; the
    # guard must catch each blow-up (more substeps, or a halt with a reason), never show it.
    sim = run_hard({"cloth.resolution": 12, "behavior.solver": "springs",
                    "behavior.integrator": integrator, "behavior.stiffness": 1e5},
                   min_steps=2000, max_stretch=1.0, allow_halt=True)
    if integrator == "implicit_euler":
        assert sim.recoveries == 0 and not sim.halted
    if sim.halted:
        assert "implicit_euler" in sim.halted


def test_hurricane_wind():
    # 70 m/s gusts, a category-5 hurricane: ~3 kPa on a 0.2 kg sheet, some 15,000 m/s². Four
    # PBD passes cannot hold that rigid, so the sheet stretches, boundedly.
    run_hard({"forces.wind": True, "forces.wind_strength": 70.0, "forces.wind_mode": "gusty",
              "cloth.pinned": "one_edge", "forces.wind_direction": [1.0, -0.3, 0.5]},
             max_stretch=3.0)


def test_supersonic_wind_stays_bounded():
    # 500 m/s would shred real cloth; the sheet may stretch, but stays finite and the speed
    # clamp bounds every particle's step.
    run_hard({"forces.wind": True, "forces.wind_strength": 500.0, "forces.wind_mode": "gusty",
              "cloth.pinned": "one_edge", "forces.wind_direction": [1.0, -0.3, 0.5]},
             max_stretch=12.0)


@pytest.mark.parametrize("field", ["black_hole", "anti_gravity", "vortex", "tractor_beam"])
def test_enormous_field_strength(field):
    # 10⁵ m/s² (10,000 g): no cloth survives that; the solver must stay finite and bounded,
    # each particle's step clamped to max_speed·h.
    run_hard({"forces.custom": field, "forces.custom_strength": 1e5, "cloth.resolution": 16},
             max_stretch=12.0)


@pytest.mark.parametrize("obj", ["sphere", "box"])
def test_drop_from_several_metres_onto_object(obj):
    # Off-centre over the box, so the sheet lands on an edge.
    sim = run_hard({"scene.object": obj, "cloth.pinned": "none", "cloth.height": 5.0,
                    "behavior.substeps": 8})
    assert sim.step.penetration(sim.state.x) <= sim.scene.scene.thickness + 1e-3


def test_drop_onto_box_edge():
    from cloth_tui.scene import SceneObject
    from .hardcase import make
    from cloth_tui.sim.runner import Simulation

    s = make({"cloth.pinned": "none", "cloth.height": 4.0, "behavior.substeps": 8})
    s.objects = [SceneObject(type="box", center=[0.45, -0.25, 0.0], size=[0.5, 0.5, 0.5])]
    sim = Simulation(s)
    for _ in range(600):
        sim.advance_frame()
        assert sim.state.is_finite()
    st = sim.stats()
    assert st["penetration"] <= s.scene.thickness + 1e-3 and st["max_speed"] < 5.0


def test_heavy_rain():
    # 5000 drops/s, each displacing a particle 0.2 m (five grid spacings): the last frame's
    # fresh drops leave constraints stretched, the rest of the sheet holds.
    sim = run_hard({"forces.rain": True, "forces.rain_rate": 5000.0,
                    "forces.rain_strength": 0.2}, max_stretch=3.0)
    assert sim.stats()["mean_stretch"] < 0.2


def test_wave_faster_than_max_speed_is_refused():
    from cloth_tui.scene import Scene, SceneError
    with pytest.raises(SceneError, match="max_speed"):
        Scene().with_value("behavior.wave", True).with_value("behavior.wave_amplitude", 20.0) \
            .with_value("behavior.wave_frequency", 100.0)


@pytest.mark.parametrize("amplitude, frequency", [(5.0, 1.5), (0.15, 50.0), (15.0, 0.5)])
def test_wave_at_extremes(amplitude, frequency):
    run_hard({"behavior.wave": True, "behavior.wave_amplitude": amplitude,
              "behavior.wave_frequency": frequency, "scene.floor": False,
              "cloth.resolution": 16}, max_stretch=50.0)


def test_self_collision_in_a_storm():
    run_hard({"behavior.self_collision": "hash", "forces.wind": True,
              "forces.wind_strength": 100.0, "forces.wind_mode": "gusty", "forces.rain": True,
              "forces.rain_rate": 500.0, "cloth.pinned": "one_edge", "cloth.resolution": 20},
             min_steps=2000, max_stretch=1.0)
