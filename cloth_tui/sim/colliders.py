"""Colliders: positional correction with the original's friction rule.

A particle found inside an object (closer than `thickness` to its surface) goes to
    new = F · posFriction + (1 − F) · posNoFriction
where posNoFriction is the nearest point on the surface (offset by the thickness) and
posFriction is the particle's previous position carried along with the object's motion;
the blend is used only when the previous position was outside, as in the original.
"""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np
from numba import njit


@dataclass(frozen=True)
class ObjectPose:
    """Where an object is now, for the renderer (a copy; never shared with the kernels)."""
    type: str
    center: tuple
    radius: float = 0.0
    size: tuple = (0.0, 0.0, 0.0)
    normal: tuple = (0.0, 1.0, 0.0)


@njit(nogil=True, cache=True, fastmath=True)
def collide_floor(x, x_prev, inv_mass, height, friction):
    for i in range(x.shape[0]):
        if inv_mass[i] == 0.0 or x[i, 1] >= height:
            continue
        if x_prev[i, 1] >= height:
            x[i, 0] = friction * x_prev[i, 0] + (1.0 - friction) * x[i, 0]
            x[i, 2] = friction * x_prev[i, 2] + (1.0 - friction) * x[i, 2]
        x[i, 1] = height


class CollideFloor:
    name = "collide_floor"

    def __init__(self, model, height: float, friction: float, thickness: float):
        self.inv_mass = model.inv_mass
        self.surface = height
        self.height = height + thickness
        self.friction = friction

    def apply(self, state, h):
        collide_floor(state.x, state.x_prev, self.inv_mass, self.height, self.friction)

    def penetration(self, x: np.ndarray) -> float:
        """Deepest any particle is below the floor's surface, m."""
        return float(max(0.0, self.surface - x[:, 1].min()))


def build_colliders(scene, model) -> list:
    """Collider effects the scene enables: the floor, then objects."""
    s = scene.scene
    out = []
    if s.floor:
        out.append(CollideFloor(model, s.floor_height, s.friction, s.thickness))
    return out
