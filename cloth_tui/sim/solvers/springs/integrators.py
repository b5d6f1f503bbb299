"""Force-based cloth: Hooke springs along the model's edges, advanced by a chosen integrator.

Every enabled constraint of the model (structural, shear, bending) is a spring of stiffness
k = behavior.stiffness (N/m) with damping kd = behavior.spring_damping (N·s/m) acting along it:

    f_a = [k (L − L0) + kd ((v_b − v_a)·n)] n,   f_b = −f_a,   n = (x_b − x_a)/L

plus a drag −c·m·v with the rate c = −ln(1 − damping)/0.018 s⁻¹ (the same decay per second as
the PBD solver's `damping`, see stages.damping_factor) and the scene's force effects
(gravity, ...). The state y = (x, v) is advanced by behavior.integrator over one substep h:

    explicit_euler    x' = x + h v,              v' = v + h a(x, v)                  order 1
    symplectic_euler  v' = v + h a(x, v),        x' = x + h v'                       order 1
    verlet            velocity Verlet (kick–drift–kick):                            order 2
                        v½ = v + h/2 a(x, v),  x' = x + h v½,
                        v' = v½ + h/2 a(x', v + h a(x, v))
                      (the closing kick evaluates velocity-dependent forces at an
                      Euler-predicted v', so damping does not drop it to order 1; with
                      velocity-independent forces it is exactly velocity Verlet, which is
                      symplectic)
    midpoint          explicit midpoint (RK2)                                        order 2
    rk4               classical Runge–Kutta                                          order 4
    implicit_euler    linearised backward Euler, one Newton step per substep:       order 1
                        (M − h²K − hD) Δv = h (f + h K v),  v' = v + Δv,  x' = x + h v'
                      K = ∂f/∂x, D = ∂f/∂v of the springs and the drag. The transverse part
                      of each spring's K is clamped to tension (max(0, 1 − L0/L)) so the
                      matrix stays symmetric positive definite; it is solved matrix-free by
                      Jacobi-preconditioned conjugate gradients, warm-started from the last
                      substep's Δv (relative residual 1e-6, at most CG_MAX_ITERATIONS
                      iterations; implicit_euler.py).

The integrator's move of each particle is then cut to MOVE_LIMIT times max_speed·h
(limit_moves). After that, the substep runs the contact effects (colliders, self-collision; they
read x_prev = the substep's start positions), then the pins, then `correct_velocities`: a
particle a contact moved gets v = (x − x_prev)/h (the PBD rule, so contacts behave as with
pbd), pinned particles get their anchors' velocity, every other particle keeps the
integrator's velocity (which keeps the integrator's order). Speeds are clamped to max_speed.
Force effects (protocols.ForceEffect) are evaluated by the integrator at every stage through
`accumulate(x, v, t, out_accel)`; a kinematic one (forces.Wave, which moves the pins'
anchors) has its `apply` run once at the start of each substep instead.
"""

from __future__ import annotations

import math

import numpy as np

from ....original import ORIGINAL_TIMESTEP
from ..registry import integrator_for
from .implicit_euler import CG_MAX_ITERATIONS, CG_TOLERANCE, DEGENERATE_LENGTH, solve_implicit_euler
from ...jit import kernel
from ...params import StepParams
from ...protocols import ForceEffect

ORDERS = {"explicit_euler": 1, "symplectic_euler": 1, "verlet": 2, "midpoint": 2, "rk4": 4,
          "implicit_euler": 1}


def drag_rate(damping: float) -> float:
    """The scene's `damping` (share of velocity lost per 18 ms) as a rate c, s⁻¹."""
    return -math.log1p(-damping) / ORIGINAL_TIMESTEP


# --- kernels ----------------------------------------------------------------------------------

@kernel()
def add_spring_accel(x, v, edges, rest, alive, inv_mass, k, kd, drag, out):
    """out += (spring forces)/m − drag·v for every free particle; torn springs pull no more."""
    for e in range(edges.shape[0]):
        if not alive[e]:
            continue
        a = edges[e, 0]
        b = edges[e, 1]
        dx = x[b, 0] - x[a, 0]
        dy = x[b, 1] - x[a, 1]
        dz = x[b, 2] - x[a, 2]
        L = math.sqrt(dx * dx + dy * dy + dz * dz)
        if L < DEGENERATE_LENGTH:
            continue
        nx = dx / L
        ny = dy / L
        nz = dz / L
        fs = k * (L - rest[e])
        if kd != 0.0:
            fs += kd * ((v[b, 0] - v[a, 0]) * nx + (v[b, 1] - v[a, 1]) * ny
                        + (v[b, 2] - v[a, 2]) * nz)
        wa = inv_mass[a] * fs
        wb = inv_mass[b] * fs
        out[a, 0] += wa * nx
        out[a, 1] += wa * ny
        out[a, 2] += wa * nz
        out[b, 0] -= wb * nx
        out[b, 1] -= wb * ny
        out[b, 2] -= wb * nz
    if drag != 0.0:
        for i in range(x.shape[0]):
            if inv_mass[i] != 0.0:
                out[i, 0] -= drag * v[i, 0]
                out[i, 1] -= drag * v[i, 1]
                out[i, 2] -= drag * v[i, 2]


@kernel()
def zero_rows(a, rows):
    for k in range(rows.shape[0]):
        i = rows[k]
        a[i, 0] = 0.0
        a[i, 1] = 0.0
        a[i, 2] = 0.0


@kernel()
def restore_rows(a, b, rows):
    for k in range(rows.shape[0]):
        i = rows[k]
        a[i, 0] = b[i, 0]
        a[i, 1] = b[i, 1]
        a[i, 2] = b[i, 2]


@kernel()
def finish_velocities(x, x_prev, x_pred, v, inv_mass, inv_h, max_speed):
    """After contacts and pins: a particle a contact (or pin) moved takes the PBD velocity
    (x − x_prev)/h; the others keep the integrator's. Speeds are clamped to max_speed."""
    vmax2 = max_speed * max_speed
    for i in range(x.shape[0]):
        moved = (x[i, 0] != x_pred[i, 0]) or (x[i, 1] != x_pred[i, 1]) or \
                (x[i, 2] != x_pred[i, 2])
        if inv_mass[i] == 0.0 or moved:
            v[i, 0] = (x[i, 0] - x_prev[i, 0]) * inv_h
            v[i, 1] = (x[i, 1] - x_prev[i, 1]) * inv_h
            v[i, 2] = (x[i, 2] - x_prev[i, 2]) * inv_h
        s2 = v[i, 0] * v[i, 0] + v[i, 1] * v[i, 1] + v[i, 2] * v[i, 2]
        if s2 > vmax2:
            s = max_speed / math.sqrt(s2)
            v[i, 0] *= s
            v[i, 1] *= s
            v[i, 2] *= s


# An integrator's move of a particle is cut to this many times the speed limit's reach in a
# substep. A step that diverges then stays representable (the floor's projection of a point
# 10²⁰ m below it rounds to the floor's height), while it still stretches its springs far
# past what the guard reads as diverged; a shorter move is the integrator's own.
MOVE_LIMIT = 10.0


@kernel()
def limit_moves(x, x_prev, h, max_speed):
    """A particle the integrator moved farther than MOVE_LIMIT·max_speed·h is brought back
    along its path to that distance (a linearised step on a stiff, torn or tangled sheet
    can ask for moves of 10²⁰ m). The velocity is clamped to max_speed afterwards, by
    finish_velocities."""
    reach = MOVE_LIMIT * max_speed * h
    reach2 = reach * reach
    for i in range(x.shape[0]):
        dx = x[i, 0] - x_prev[i, 0]
        dy = x[i, 1] - x_prev[i, 1]
        dz = x[i, 2] - x_prev[i, 2]
        d2 = dx * dx + dy * dy + dz * dz
        if d2 > reach2:  # false for NaN: the guard sees a non-finite state as it is
            s = reach / math.sqrt(d2)
            x[i, 0] = x_prev[i, 0] + s * dx
            x[i, 1] = x_prev[i, 1] + s * dy
            x[i, 2] = x_prev[i, 2] + s * dz


# --- effects ----------------------------------------------------------------------------------

class IntegrateSprings:
    """One substep of the spring system with the chosen integrator. Named after it
    (integrate_rk4, integrate_implicit_euler, ...). Sets x_prev to the start positions and
    leaves the integrator's end positions in `x_pred` for `correct_velocities`."""

    def __init__(self, model, behavior, force_effects: list[ForceEffect], params: StepParams):
        self.integrator = integrator_for(behavior)  # `auto` resolved for springs
        if self.integrator not in ORDERS:
            raise ValueError(f"unknown integrator {self.integrator!r}")
        self.name = f"integrate_{self.integrator}"
        self.model = model
        self.params = params
        self.forces = [f.accumulate for f in force_effects if not f.kinematic]
        # Kinematic drives (the wave moves pin anchors) run once per substep, as with pbd.
        self.kinematic = [f for f in force_effects if f.kinematic]
        self._advance = {"explicit_euler": self._explicit_euler,
                         "symplectic_euler": self._symplectic_euler, "verlet": self._verlet,
                         "midpoint": self._midpoint, "rk4": self._rk4,
                         "implicit_euler": self._implicit_euler}[self.integrator]
        self.cg_iterations = 0
        n = model.num_particles
        z = lambda: np.zeros((n, 3))  # noqa: E731
        self.x_pred = z()
        self._a = [z() for _ in range(4)]
        self._xs, self._vs, self._vt = z(), z(), z()
        self._free = np.asarray(model.inv_mass != 0.0)
        self._alive = np.ones(model.num_constraints, np.uint8)  # the state's, set by apply
        if self.integrator == "implicit_euler":
            m = max(1, model.num_constraints)
            self._dirs = np.zeros((m, 3))
            self._tension = np.zeros(m)
            self.dv = z()  # Δv of the last substep: the next solve's warm start
            self._cg = [z() for _ in range(4)]

    @property
    def k(self) -> float:
        return float(self.params.stiffness)

    @property
    def kd(self) -> float:
        return float(self.params.spring_damping)

    @property
    def drag(self) -> float:
        return drag_rate(self.params.damping)

    def accel(self, x, v, t, out):
        """out = a(x, v, t): external forces, springs, drag; zero on pinned particles."""
        out.fill(0.0)
        for f in self.forces:
            f(x, v, t, out)
        m = self.model
        add_spring_accel(x, v, m.edges, m.rest_length, self._alive, m.inv_mass, self.k,
                         self.kd, self.drag, out)
        zero_rows(out, m.pinned)
        return out

    def apply(self, state, h):
        x, v, t = state.x, state.v, state.t
        self._alive = state.alive
        for effect in self.kinematic:
            effect.apply(state, h)
        state.x_prev[...] = x
        self._advance(x, v, t, h)
        limit_moves(x, state.x_prev, h, self.params.max_speed)
        restore_rows(x, state.x_prev, self.model.pinned)  # pins move only to their anchors
        self.x_pred[...] = x
        state.accel.fill(0.0)

    # Each integrator advances x, v in place over h.
    def _explicit_euler(self, x, v, t, h):
        a = self.accel(x, v, t, self._a[0])
        x += h * v
        v += h * a

    def _symplectic_euler(self, x, v, t, h):
        a = self.accel(x, v, t, self._a[0])
        v += h * a
        x += h * v

    def _verlet(self, x, v, t, h):
        a0 = self.accel(x, v, t, self._a[0])
        vt = self._vt
        np.multiply(a0, h, out=vt)
        vt += v                      # Euler-predicted v' (for velocity-dependent forces)
        v += 0.5 * h * a0            # kick
        x += h * v                   # drift
        a1 = self.accel(x, vt, t + h, self._a[1])
        v += 0.5 * h * a1            # kick

    def _midpoint(self, x, v, t, h):
        xs, vs = self._xs, self._vs
        a0 = self.accel(x, v, t, self._a[0])
        np.multiply(v, 0.5 * h, out=xs)
        xs += x
        np.multiply(a0, 0.5 * h, out=vs)
        vs += v
        a1 = self.accel(xs, vs, t + 0.5 * h, self._a[1])
        x += h * vs
        v += h * a1

    def _rk4(self, x, v, t, h):
        xs, vs = self._xs, self._vs
        k1 = self.accel(x, v, t, self._a[0])          # k1 = (v, a1)
        np.multiply(v, 0.5 * h, out=xs); xs += x      # noqa: E702
        np.multiply(k1, 0.5 * h, out=vs); vs += v     # noqa: E702
        v2 = vs.copy()
        k2 = self.accel(xs, vs, t + 0.5 * h, self._a[1])
        np.multiply(v2, 0.5 * h, out=xs); xs += x     # noqa: E702
        np.multiply(k2, 0.5 * h, out=vs); vs += v     # noqa: E702
        v3 = vs.copy()
        k3 = self.accel(xs, vs, t + 0.5 * h, self._a[2])
        np.multiply(v3, h, out=xs); xs += x           # noqa: E702
        np.multiply(k3, h, out=vs); vs += v           # noqa: E702
        v4 = vs.copy()
        k4 = self.accel(xs, vs, t + h, self._a[3])
        x += (h / 6.0) * (v + 2.0 * v2 + 2.0 * v3 + v4)
        v += (h / 6.0) * (k1 + 2.0 * k2 + 2.0 * k3 + k4)

    def _implicit_euler(self, x, v, t, h):
        m = self.model
        a = self.accel(x, v, t, self._a[0])
        r, z, p, q = self._cg
        self.cg_iterations = solve_implicit_euler(
            x, v, a, m.mass, self._free, m.edges, m.rest_length, self._alive, self.k, self.kd,
            self.drag, h, self._dirs, self._tension, self.dv, r, z, p, q, self._a[1], CG_TOLERANCE,
            CG_MAX_ITERATIONS)


class CorrectVelocities:
    name = "correct_velocities"

    def __init__(self, model, integrate: IntegrateSprings, params: StepParams):
        self.inv_mass = model.inv_mass
        self.integrate = integrate
        self.params = params

    def apply(self, state, h):
        finish_velocities(state.x, state.x_prev, self.integrate.x_pred, state.v, self.inv_mass,
                          1.0 / h, self.params.max_speed)
