"""What a run reports: the full statistics measured on demand and the immutable snapshot the
renderer and the UI get each frame."""

from __future__ import annotations

from dataclasses import dataclass
from typing import TYPE_CHECKING

import numpy as np

from ..model import ClothModel
from ..state import ClothState
from .measures import stretch
from .run_stats import RunStats

if TYPE_CHECKING:
    from ...scene import Scene
    from ..pipeline import Step


@dataclass(frozen=True)
class Snapshot:
    """What the renderer and the UI get each frame: copies, never the live arrays. `stats`
    are complete only every STATS_INTERVAL s (see Simulation.snapshot)."""
    positions: np.ndarray
    frame: int
    t: float
    stats: RunStats
    model: ClothModel
    scene: Scene
    objects: tuple = ()  # ObjectPose of every object, where it is at time t
    alive: np.ndarray | None = None  # which constraints are intact; None: all (nothing torn)


def measured_stats(model: ClothModel, state: ClothState, scene: Scene, step: Step,
                   finite: bool, error: float | None, error_tolerance: float,
                   energy_tolerance: float | None, energy: float,
                   penetration: float) -> RunStats:
    """The costly statistics of the sheet as it is now (`error`: its solve error, None
    where the solver leaves none to bound)."""
    x = state.x
    max_s, mean_s = stretch(model, x, state.alive) if finite else (float("nan"),) * 2
    speed = np.sqrt(np.einsum("ij,ij->i", state.v, state.v))
    return RunStats(
        measured=True,
        particles=model.num_particles, constraints=model.num_constraints,
        finite=finite, min_y=float(x[:, 1].min()), max_speed=float(speed.max()),
        max_stretch=max_s, mean_stretch=mean_s, solver=scene.behavior.solver,
        error=error,
        # springs have no constraint solve to be off its equilibrium: nothing to bound
        error_tolerance=None if error is None else error_tolerance,
        energy_tolerance=energy_tolerance, energy=energy,
        penetration=penetration, effects=tuple(step.names),
        material=None if scene.material is None else scene.material.name)


def snapshot_of(model: ClothModel, state: ClothState, scene: Scene, step: Step, frames: int,
                stats: RunStats) -> Snapshot:
    """Copies of the sheet now, with every object where it is at time t."""
    poses = tuple(p for p in (c.pose(state.t) for c in step.colliders) if p)
    alive = state.alive.copy() if state.torn else None
    return Snapshot(state.x.copy(), frames, state.t, stats, model, scene, poses, alive)
