"""The bench's peer: the bare step as one plain serial numba loop, the way a careful user
would write it without this project (array-of-structures positions, a loop over the
constraint list in colour order, one thread). The same work as the project's step: gravity,
Verlet with damping and the speed clamp, K passes of Gauss-Seidel, pins, velocities."""

from __future__ import annotations

import math

from ..sim.jit import kernel
from ..sim.effects.stages import damping_factor
from ..sim.solvers.xpbd.constraints import project_constraints


@kernel()
def serial_substep(x, x_prev, v, inv_mass, edges, rest, alive, color_offsets, lam, pinned,
                   anchors, h, keep, gravity, max_speed, iterations):
    h2 = h * h
    max_step = max_speed * h
    for i in range(x.shape[0]):
        x_prev[i, 0] = x[i, 0]
        x_prev[i, 1] = x[i, 1]
        x_prev[i, 2] = x[i, 2]
        if inv_mass[i] == 0.0:
            continue
        dx = v[i, 0] * keep * h
        dy = v[i, 1] * keep * h - gravity * h2
        dz = v[i, 2] * keep * h
        d2 = dx * dx + dy * dy + dz * dz
        if d2 > max_step * max_step:
            s = max_step / math.sqrt(d2)
            dx *= s
            dy *= s
            dz *= s
        x[i, 0] += dx
        x[i, 1] += dy
        x[i, 2] += dz
    project_constraints(x, inv_mass, edges, rest, alive, color_offsets, lam, 0.0, iterations)
    for k in range(pinned.shape[0]):
        p = pinned[k]
        x[p, 0] = anchors[k, 0]
        x[p, 1] = anchors[k, 1]
        x[p, 2] = anchors[k, 2]
    inv_h = 1.0 / h
    for i in range(x.shape[0]):
        v[i, 0] = (x[i, 0] - x_prev[i, 0]) * inv_h
        v[i, 1] = (x[i, 1] - x_prev[i, 1]) * inv_h
        v[i, 2] = (x[i, 2] - x_prev[i, 2]) * inv_h


class SerialStep:
    """`substep(state)` runs serial_substep on a ClothState of `model`."""

    def __init__(self, model, h: float, iterations: int, damping: float, gravity: float,
                 max_speed: float):
        import numpy as np

        self.model, self.h, self.iterations = model, h, iterations
        self.keep = damping_factor(damping, h)
        self.gravity, self.max_speed = gravity, max_speed
        self.lam = np.zeros(model.num_constraints)

    def substep(self, state) -> None:
        m = self.model
        serial_substep(state.x, state.x_prev, state.v, m.inv_mass, m.edges, m.rest_length,
                       state.alive, m.color_offsets, self.lam, m.pinned, state.anchors, self.h,
                       self.keep, self.gravity, self.max_speed, self.iterations)
