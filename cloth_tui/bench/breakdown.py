"""Where a scene's step spends its time: each effect present, timed over many frames.

Effects absent from the scene are absent from the table: that is the point, a scene pays
only for what it enables."""

from __future__ import annotations

import time
from collections import defaultdict

from ..scene import Scene
from ..sim.run.runner import Simulation


class _Timed:
    """Wraps an effect, adding the wall time of each `apply` to a shared table."""

    def __init__(self, effect, table: dict):
        self.effect, self.table, self.name = effect, table, effect.name

    def apply(self, state, h):
        t0 = time.perf_counter()
        self.effect.apply(state, h)
        self.table[self.name] += time.perf_counter() - t0


def breakdown(scene: Scene, frames: int = 120, warmup: int = 10) -> dict:
    sim = Simulation(scene)
    for _ in range(warmup):
        sim.advance_frame()  # compile and settle
    table: dict[str, float] = defaultdict(float)
    step = sim.step
    step.effects = [_Timed(e, table) for e in step.effects]
    step.frame_effects = [_Timed(e, table) for e in step.frame_effects]
    t0 = time.perf_counter()
    for _ in range(frames):
        step.frame(sim.state)
    total = time.perf_counter() - t0
    effects = [{"effect": name, "ms_per_frame": 1e3 * table[name] / frames,
                "share": table[name] / total if total else 0.0} for name in step.names]
    return {"scene": scene.name, "particles": sim.model.num_particles,
            "substeps": step.substeps, "frames": frames,
            "ms_per_frame": 1e3 * total / frames, "effects": effects}

