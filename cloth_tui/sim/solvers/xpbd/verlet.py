"""The position-based solvers' prediction and velocity update, shared by pbd, xpbd and
hpbd: integrate_verlet (x_prev ← x; x ← x + (1−D)·v·h + a·h²) after the force effects have
added to state.accel, and update_velocities (v ← (x − x_prev)/h, clamped to max_speed).
Compiled with nogil so the simulation thread leaves the GIL to the UI.
"""

from __future__ import annotations

import math


from ...jit import kernel
from ...fabric.material import damping_factor as decay_factor
from ...params import StepParams
from ...effects.stages import damping_factor


@kernel()
def integrate_verlet(x, x_prev, v, accel, inv_mass, h, keep, max_speed):
    """Position Verlet with damping. The step's displacement, velocity and acceleration terms
    together, is clamped to max_speed·h: no particle outruns the colliders' thickness or
    the constraints, whatever force or impulse acts on it."""
    h2 = h * h
    max_step = max_speed * h
    for i in range(x.shape[0]):
        if inv_mass[i] == 0.0:
            x_prev[i, 0] = x[i, 0]
            x_prev[i, 1] = x[i, 1]
            x_prev[i, 2] = x[i, 2]
        else:
            dx = v[i, 0] * keep * h + accel[i, 0] * h2
            dy = v[i, 1] * keep * h + accel[i, 1] * h2
            dz = v[i, 2] * keep * h + accel[i, 2] * h2
            d2 = dx * dx + dy * dy + dz * dz
            if d2 > max_step * max_step:
                s = max_step / math.sqrt(d2)
                dx *= s
                dy *= s
                dz *= s
            x_prev[i, 0] = x[i, 0]
            x_prev[i, 1] = x[i, 1]
            x_prev[i, 2] = x[i, 2]
            x[i, 0] += dx
            x[i, 1] += dy
            x[i, 2] += dz
        accel[i, 0] = 0.0
        accel[i, 1] = 0.0
        accel[i, 2] = 0.0


@kernel()
def update_velocities(x, x_prev, v, inv_mass, inv_h, max_speed):
    """v ← (x − x_prev)/h, a free particle's clamped to max_speed as the springs' are: a
    contact or constraint correction at a short substep would otherwise read as a speed the
    next prediction clamps anyway (a 5 cm push at h = 2 µs is 25 km/s). Pins keep the speed
    they are driven at. A NaN fails the comparison and stays visible."""
    vmax2 = max_speed * max_speed
    for i in range(x.shape[0]):
        v[i, 0] = (x[i, 0] - x_prev[i, 0]) * inv_h
        v[i, 1] = (x[i, 1] - x_prev[i, 1]) * inv_h
        v[i, 2] = (x[i, 2] - x_prev[i, 2]) * inv_h
        s2 = v[i, 0] * v[i, 0] + v[i, 1] * v[i, 1] + v[i, 2] * v[i, 2]
        if inv_mass[i] != 0.0 and s2 > vmax2:
            s = max_speed / math.sqrt(s2)
            v[i, 0] *= s
            v[i, 1] *= s
            v[i, 2] *= s


class IntegrateVerlet:
    """The prediction. Its damping is the model's fabric's decay rate where the sheet has a
    fabric (the model is the one channel of a material's numbers), else behavior.damping,
    read from `params` as it runs."""
    name = "integrate_verlet"

    def __init__(self, model, params: StepParams):
        self.inv_mass = model.inv_mass
        self.fabric = model.fabric
        self.params = params

    def retune(self, model) -> None:
        """Take the fabric of a model refitted with new numbers (model.refitted)."""
        self.fabric = model.fabric

    def keep(self, h: float) -> float:
        """Velocity kept over a substep of h: the fabric's decay rate, or behavior.damping's
        share per 18 ms."""
        if self.fabric is not None:
            return decay_factor(self.fabric.material.damping, h)
        return damping_factor(self.params.damping, h)

    def apply(self, state, h):
        integrate_verlet(state.x, state.x_prev, state.v, state.accel, self.inv_mass, h,
                         self.keep(h), self.params.max_speed)


class UpdateVelocities:
    name = "update_velocities"

    def __init__(self, model, params: StepParams):
        self.inv_mass = model.inv_mass
        self.params = params

    def apply(self, state, h):
        update_velocities(state.x, state.x_prev, state.v, self.inv_mass, 1.0 / h,
                          self.params.max_speed)
