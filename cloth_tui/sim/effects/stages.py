"""Stages every solver's substep shares: pins, long-range tethers, and the damping rule."""

from __future__ import annotations

import math


from ...original import ORIGINAL_TIMESTEP
from ..jit import kernel


def damping_factor(damping: float, h: float) -> float:
    """Velocity kept per step of length h. `damping` is the share lost per 18 ms (the
    original's step), so the decay rate −ln(1−d)/0.018 s⁻¹ does not depend on the timestep."""
    return (1.0 - damping) ** (h / ORIGINAL_TIMESTEP)


@kernel()
def apply_pins(x, pinned, anchors):
    for k in range(pinned.shape[0]):
        i = pinned[k]
        x[i, 0] = anchors[k, 0]
        x[i, 1] = anchors[k, 1]
        x[i, 2] = anchors[k, 2]


@kernel()
def enforce_tethers(x, pinned, anchors, tether_pin, tether_length):
    """Long-range attachments (Kim, Chentanez & Müller 2012): a particle farther from its
    nearest pin than on the flat sheet is pulled back onto that sphere. Each tether moves one
    particle, so one pass is exact and order-free."""
    for i in range(x.shape[0]):
        k = tether_pin[i]
        if k < 0:
            continue
        dx = x[i, 0] - anchors[k, 0]
        dy = x[i, 1] - anchors[k, 1]
        dz = x[i, 2] - anchors[k, 2]
        d2 = dx * dx + dy * dy + dz * dz
        limit = tether_length[i]
        if d2 > limit * limit:
            s = limit / math.sqrt(d2)
            x[i, 0] = anchors[k, 0] + dx * s
            x[i, 1] = anchors[k, 1] + dy * s
            x[i, 2] = anchors[k, 2] + dz * s


class EnforceTethers:
    name = "enforce_tethers"

    def __init__(self, model):
        self.model = model

    def apply(self, state, h):
        if state.torn:
            return  # a tether bounds by the uncut sheet's geodesic, which a tear may cut
        m = self.model
        enforce_tethers(state.x, m.pinned, state.anchors, m.tether_pin, m.tether_length)


class ApplyPins:
    name = "apply_pins"

    def __init__(self, model):
        self.pinned = model.pinned

    def apply(self, state, h):
        apply_pins(state.x, self.pinned, state.anchors)
