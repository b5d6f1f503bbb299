"""ClothState: what changes as the sheet simulates."""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np

from .model import ClothModel
from .effects.pins import hard_anchors, start_positions


@dataclass
class ClothState:
    x: np.ndarray       # (N, 3) positions, m
    x_prev: np.ndarray  # (N, 3) positions at the start of the current substep, m
    v: np.ndarray       # (N, 3) velocities, m/s
    accel: np.ndarray   # (N, 3) accumulated external acceleration of this substep, m/s²
    anchors: np.ndarray  # (K, 3) where the pinned particles are held (moved by the wave, pin keys)
    alive: np.ndarray   # (M,) uint8: 1 for a constraint in the solve, 0 once torn (tearing.py)
    t: float = 0.0      # simulated time, s
    steps: int = 0      # substeps taken
    torn: int = 0       # constraints broken (alive == 0)

    @classmethod
    def from_model(cls, model: ClothModel) -> "ClothState":
        x = start_positions(model)
        return cls(x=x, x_prev=x.copy(), v=np.zeros_like(x), accel=np.zeros_like(x),
                   anchors=hard_anchors(model, 0.0),
                   alive=np.ones(model.num_constraints, dtype=np.uint8))

    def copy(self) -> "ClothState":
        return ClothState(self.x.copy(), self.x_prev.copy(), self.v.copy(), self.accel.copy(),
                          self.anchors.copy(), self.alive.copy(), self.t, self.steps, self.torn)

    def restore(self, other: "ClothState") -> None:
        """Copy another state into this one's arrays (kernels keep their references)."""
        for name in ("x", "x_prev", "v", "accel", "anchors", "alive"):
            getattr(self, name)[...] = getattr(other, name)
        self.t, self.steps, self.torn = other.t, other.steps, other.torn

    def is_finite(self) -> bool:
        return bool(np.isfinite(self.x).all() and np.isfinite(self.v).all())
