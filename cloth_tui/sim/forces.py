"""External forces, as accelerations added to `state.accel` before integration."""

from __future__ import annotations

from numba import njit


@njit(nogil=True, cache=True, fastmath=True)
def add_uniform_acceleration(accel, inv_mass, ax, ay, az):
    for i in range(accel.shape[0]):
        if inv_mass[i] != 0.0:
            accel[i, 0] += ax
            accel[i, 1] += ay
            accel[i, 2] += az


class Gravity:
    name = "gravity"

    def __init__(self, model, strength: float):
        self.inv_mass = model.inv_mass
        self.g = strength

    def apply(self, state, h):
        add_uniform_acceleration(state.accel, self.inv_mass, 0.0, -self.g, 0.0)


def build_forces(scene, model) -> list:
    """Force effects the scene enables, in order."""
    f = scene.forces
    out = []
    if f.gravity and f.gravity_strength > 0:
        out.append(Gravity(model, f.gravity_strength))
    return out
