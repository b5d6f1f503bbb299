"""Hard cases for hierarchical PBD: the scenes of test_hard_cases.py that reach its coarse
levels' own code (tiny sheets with none, every pin layout, a crushed sheet, violent loads,
drops onto objects), under the same per-frame checks and stretch bounds."""

import numpy as np
import pytest

from cloth_tui.scene import PIN_MODES

from ..hardcase import run_hard

HPBD = {"behavior.solver": "hpbd"}


@pytest.mark.parametrize("n", [2, 3, 5])
def test_tiny_sheets(n):
    run_hard({**HPBD, "cloth.resolution": n, "cloth.pinned": "none"})
    run_hard({**HPBD, "cloth.resolution": n, "cloth.pinned": "corners"})


@pytest.mark.parametrize("mode", PIN_MODES)
def test_every_pin_mode(mode):
    sim = run_hard({**HPBD, "cloth.pinned": mode, "cloth.resolution": 20}, min_steps=2000)
    m = sim.model
    np.testing.assert_array_equal(sim.state.x[m.pinned], m.rest_positions[m.pinned])


def test_coincident_particles():
    def crush(sim, frame):
        if frame == 0:
            sim.state.x[:] = sim.state.x[0]  # every particle at one point
    # the bounds of test_hard_cases' crushed sheet: folds lock some constraints stretched
    sim = run_hard({**HPBD, "cloth.pinned": "none", "cloth.resolution": 10}, on_frame=crush,
                   max_stretch=1.5, max_mean=0.06)
    assert np.ptp(sim.state.x[:, 0]) > 0.3


def test_hurricane_wind():
    run_hard({**HPBD, "forces.wind": True, "forces.wind_strength": 70.0,
              "forces.wind_mode": "gusty", "cloth.pinned": "one_edge",
              "forces.wind_direction": [1.0, -0.3, 0.5]})


def test_strong_gravity_and_one_substep_at_10_frames_per_second():
    run_hard({**HPBD, "forces.gravity_strength": 1000.0, "cloth.pinned": "one_edge"})
    sim = run_hard({**HPBD, "behavior.frame_rate": 10.0, "behavior.substeps": 1,
                    "behavior.iterations": 1})
    assert sim.stats().tolerance_met


@pytest.mark.parametrize("obj", ["sphere", "box"])
def test_drop_from_several_metres_onto_object(obj):
    sim = run_hard({**HPBD, "scene.object": obj, "cloth.pinned": "none", "cloth.height": 5.0,
                    "behavior.substeps": 8})
    assert sim.step.penetration(sim.state.x) <= sim.scene.scene.thickness + 1e-3
