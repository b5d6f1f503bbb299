"""Running the simulation the bake runs, frame by frame, for comparing with what was written."""

import numpy as np

from cloth_tui.scene_files import apply_overrides, load
from cloth_tui.sim.run.run_stats import RunStats
from cloth_tui.sim.run.runner import Simulation


def simulated_frames(scene_ref: str, overrides: list[str], frames: int):
    """(positions per frame from frame 1, poses per frame) of a fresh run."""
    sim = Simulation(apply_overrides(load(scene_ref), overrides))
    xs, poses = [], []
    for _ in range(frames):
        sim.advance_frame()
        snap = sim.snapshot(stats=RunStats())
        xs.append(np.array(snap.positions))
        poses.append(snap.objects)
    return xs, poses
