"""A run of a built-in scene summarised in a few numbers, to compare a later run with one
stored before a change (tests/sim/data/original_runs.json). Regenerate only on purpose:

    PYTHONPATH=. python -m tests.sim.original_run > tests/sim/data/original_runs.json
"""

from __future__ import annotations

import hashlib
import json
import sys

import numpy as np

from cloth_tui.scene_files import load
from cloth_tui.sim.run.runner import Simulation

FRAMES = 90
# The original's sheet (the built-in scene `original`) with the original's solver (pbd,
# adaptive: the default until hpbd), and with xpbd at its scalar compliance without the
# adaptive control: together they cover both solvers' scalar-α paths.
RUNS = {"original": ["behavior.solver", "pbd"],
        "original-xpbd": ["behavior.solver", "xpbd", "behavior.adaptive", False]}


def scene_of(name: str):
    overrides = RUNS[name]
    scene = load("original")
    values = dict(zip(overrides[::2], overrides[1::2]))
    return scene.with_values(values) if values else scene


def summary(name: str) -> dict:
    sim = Simulation(scene_of(name))
    for _ in range(FRAMES):
        sim.advance_frame()
    x = sim.state.x
    centre = x[(sim.model.nz // 2) * sim.model.nx + sim.model.nx // 2]
    return {"frames": FRAMES, "steps": sim.state.steps,
            "centre": [float(c) for c in centre],
            "sum": [float(s) for s in x.sum(axis=0)],
            "sum_of_squares": float((x * x).sum()),
            "sha256": hashlib.sha256(np.ascontiguousarray(x).tobytes()).hexdigest()}


if __name__ == "__main__":
    json.dump({name: summary(name) for name in RUNS}, sys.stdout, indent=1)
    sys.stdout.write("\n")
