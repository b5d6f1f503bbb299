"""The counters a run keeps (frames, wall time, retried frames, deepest penetration, why it
halted) belong to that run: a restart or a rebuilt sheet starts them again from zero."""

import numpy as np
import pytest

from cloth_tui.sim.run.runner import Simulation

from ..helpers import scene


def diverge(sim: Simulation) -> None:
    """One frame that blows up (as a solver would), which the guard undoes and retries."""
    sim.state.x[3] = np.nan
    sim.state.v[3] = np.nan
    sim.advance_frame()


def halt(sim: Simulation) -> None:
    """Frames that diverge whatever the substeps: the last good state is broken too."""
    sim._good.x[3] = np.nan
    diverge(sim)


def counters(sim: Simulation) -> dict:
    s = sim.stats()
    return {k: getattr(s, k) for k in ("frames", "wall_s", "recoveries", "penetration", "halted")}


AT_START = {"frames": 0, "wall_s": 0.0, "recoveries": 0, "penetration": 0.0,
            "halted": None}


def used_run(**overrides) -> Simulation:
    """A pbd sheet on a sphere that needed a retry and (as a hard contact can) went 1 cm deep
    into the sphere once: the solver keeps real contacts far shallower than that."""
    sim = Simulation(scene(scene__object="sphere", **overrides))
    for _ in range(20):
        sim.advance_frame()
    diverge(sim)
    sim.penetration = 0.01
    c = counters(sim)
    assert c["frames"] > 0 and c["wall_s"] > 0 and c["recoveries"] >= 1
    return sim


def test_a_new_simulation_starts_at_zero():
    assert counters(Simulation(scene())) == AT_START


def test_restart_starts_the_counters_again():
    sim = used_run()
    sim.reset()
    assert counters(sim) == AT_START


@pytest.mark.parametrize("key, value", [("cloth.resolution", 12), ("cloth.size", 0.8),
                                        ("behavior.bending", False)])
def test_a_setting_that_rebuilds_the_sheet_starts_a_new_run(key, value):
    sim = used_run()
    assert sim.set_scene(sim.scene.with_value(key, value)) is True
    assert counters(sim) == AT_START


def test_another_scene_starts_a_new_run():
    """What the app does when a scene is opened from the palette: set_scene, then reset."""
    sim = used_run()
    sim.set_scene(scene(scene__object="box", behavior__iterations=6))
    sim.reset()
    assert counters(sim) == AT_START


def test_a_halted_run_restarts_clean():
    sim = Simulation(scene())
    halt(sim)
    assert sim.halted and sim.recoveries >= 1
    sim.reset()
    assert counters(sim) == AT_START
    sim.advance_frame()
    assert sim.frames == 1 and sim.state.is_finite()


def test_a_live_setting_keeps_the_run_going():
    """Toggling wind rebuilds only the step: the same sheet runs on, and so do its frame,
    time and penetration counts. Recoveries and a halt belong to the old settings (the guard's
    verdict on them), so they clear: new settings get a fresh verdict."""
    sim = used_run()
    before = counters(sim)
    assert sim.set_scene(sim.scene.with_value("forces.wind", True)) is False
    assert counters(sim) == {**before, "recoveries": 0}
    assert sim.halted is None
