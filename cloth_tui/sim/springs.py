"""Force-based cloth: Hooke springs along the model's edges, advanced by a chosen integrator.

Every enabled constraint of the model (structural, shear, bending) is a spring of stiffness
k = behavior.stiffness (N/m) with damping kd = behavior.spring_damping (N·s/m) acting along it:

    f_a = [k (L − L0) + kd ((v_b − v_a)·n)] n,   f_b = −f_a,   n = (x_b − x_a)/L

plus a drag −c·m·v with the rate c = −ln(1 − damping)/0.018 s⁻¹ (the same decay per second as
the PBD solver's `damping`, see solvers.damping_factor) and the scene's force effects
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
                      iterations).

After the integrator, the substep runs the contact effects (colliders, self-collision; they
read x_prev = the substep's start positions), then the pins, then `correct_velocities`: a
particle a contact moved gets v = (x − x_prev)/h (the PBD rule, so contacts behave as with
pbd), pinned particles get their anchors' velocity, every other particle keeps the
integrator's velocity (which keeps the integrator's order). Speeds are clamped to max_speed.
Force effects are evaluated by the integrator at every stage through `accumulate(x, v, t,
out_accel)`; an effect without that method is adapted through its `apply(state, h)`, which
must then only add to `state.accel`. A kinematic effect (forces.Wave, which moves the pins'
anchors) also has its `apply` run once at the start of each substep.
"""

from __future__ import annotations

import math

import numpy as np
from numba import njit

from ..scene import ORIGINAL_TIMESTEP, integrator_for
from . import solvers

CG_TOLERANCE = 1e-6        # relative residual ‖r‖/‖b‖ at which conjugate gradients stops
CG_MAX_ITERATIONS = 400    # cap per substep; a stiff, large sheet may stop here (still stable)

ORDERS = {"explicit_euler": 1, "symplectic_euler": 1, "verlet": 2, "midpoint": 2, "rk4": 4,
          "implicit_euler": 1}


def drag_rate(damping: float) -> float:
    """The scene's `damping` (share of velocity lost per 18 ms) as a rate c, s⁻¹."""
    return -math.log1p(-damping) / ORIGINAL_TIMESTEP


# --- kernels ----------------------------------------------------------------------------------

@njit(nogil=True, cache=True, fastmath=True)
def add_spring_accel(x, v, edges, rest, inv_mass, k, kd, drag, out):
    """out += (spring forces)/m − drag·v for every free particle."""
    for e in range(edges.shape[0]):
        a = edges[e, 0]
        b = edges[e, 1]
        dx = x[b, 0] - x[a, 0]
        dy = x[b, 1] - x[a, 1]
        dz = x[b, 2] - x[a, 2]
        L = math.sqrt(dx * dx + dy * dy + dz * dz)
        if L < 1e-12:
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


@njit(nogil=True, cache=True, fastmath=True)
def zero_rows(a, rows):
    for k in range(rows.shape[0]):
        i = rows[k]
        a[i, 0] = 0.0
        a[i, 1] = 0.0
        a[i, 2] = 0.0


@njit(nogil=True, cache=True, fastmath=True)
def restore_rows(a, b, rows):
    for k in range(rows.shape[0]):
        i = rows[k]
        a[i, 0] = b[i, 0]
        a[i, 1] = b[i, 1]
        a[i, 2] = b[i, 2]


@njit(nogil=True, cache=True, fastmath=True)
def spring_energy(x, edges, rest, k):
    e_sum = 0.0
    for e in range(edges.shape[0]):
        a = edges[e, 0]
        b = edges[e, 1]
        dx = x[b, 0] - x[a, 0]
        dy = x[b, 1] - x[a, 1]
        dz = x[b, 2] - x[a, 2]
        c = math.sqrt(dx * dx + dy * dy + dz * dz) - rest[e]
        e_sum += 0.5 * k * c * c
    return e_sum


@njit(nogil=True, cache=True, fastmath=True)
def _spring_jacobian(x, edges, rest, dirs, tension):
    """Per spring: unit direction n and the clamped transverse factor max(0, 1 − L0/L)."""
    for e in range(edges.shape[0]):
        a = edges[e, 0]
        b = edges[e, 1]
        dx = x[b, 0] - x[a, 0]
        dy = x[b, 1] - x[a, 1]
        dz = x[b, 2] - x[a, 2]
        L = math.sqrt(dx * dx + dy * dy + dz * dz)
        if L < 1e-12:
            dirs[e, 0] = 0.0
            dirs[e, 1] = 0.0
            dirs[e, 2] = 0.0
            tension[e] = 0.0
            continue
        dirs[e, 0] = dx / L
        dirs[e, 1] = dy / L
        dirs[e, 2] = dz / L
        tension[e] = max(0.0, 1.0 - rest[e] / L)


@njit(nogil=True, cache=True, fastmath=True, inline="always")
def _spring_block_product(p, a, b, nx, ny, nz, s, ck, cd):
    """One spring's block of the system times (p_a − p_b):
    (ck·[n nᵀ + s (I − n nᵀ)] + cd·n nᵀ)(p_a − p_b), the stiffness part with the transverse
    term s clamped to tension, the damping part along the spring only."""
    ux = p[a, 0] - p[b, 0]
    uy = p[a, 1] - p[b, 1]
    uz = p[a, 2] - p[b, 2]
    nu = nx * ux + ny * uy + nz * uz
    axial = ck * (1.0 - s) * nu + cd * nu
    return ck * s * ux + axial * nx, ck * s * uy + axial * ny, ck * s * uz + axial * nz


@njit(nogil=True, cache=True, fastmath=True)
def _apply_system(p, y, edges, dirs, tension, diag_mass, free, ck, cd):
    """y = A p with A = diag_mass − ck·K̂ − cd·D̂ on the free particles, identity on pinned.
    K̂ per spring is [n nᵀ + s (I − n nᵀ)] coupling a and b (ck = h²k), D̂ = n nᵀ (cd = h·kd)."""
    for i in range(p.shape[0]):
        if free[i]:
            y[i, 0] = diag_mass[i] * p[i, 0]
            y[i, 1] = diag_mass[i] * p[i, 1]
            y[i, 2] = diag_mass[i] * p[i, 2]
        else:
            y[i, 0] = p[i, 0]
            y[i, 1] = p[i, 1]
            y[i, 2] = p[i, 2]
    for e in range(edges.shape[0]):
        a = edges[e, 0]
        b = edges[e, 1]
        wx, wy, wz = _spring_block_product(p, a, b, dirs[e, 0], dirs[e, 1], dirs[e, 2],
                                           tension[e], ck, cd)
        if free[a]:
            y[a, 0] += wx
            y[a, 1] += wy
            y[a, 2] += wz
        if free[b]:
            y[b, 0] -= wx
            y[b, 1] -= wy
            y[b, 2] -= wz


@njit(nogil=True, cache=True, fastmath=True)
def solve_implicit_euler(x, v, accel, mass, free, edges, rest, k, kd, drag, h,
                         dirs, tension, dv, r, z, p, q, diag, tol, max_iter):
    """Linearised backward Euler: solve (M − h²K − hD) Δv = h (f + h K v) for Δv by
    Jacobi-preconditioned CG, then v += Δv, x += h v. Returns the CG iterations used."""
    n = x.shape[0]
    _spring_jacobian(x, edges, rest, dirs, tension)
    ck = h * h * k
    cd = h * kd
    dm = 1.0 + h * drag
    # right-hand side h (f + h K v), f = m·accel (accel already holds springs, drag and the
    # external forces); the Jacobi diagonal of the system alongside
    for i in range(n):
        for c in range(3):
            r[i, c] = h * mass[i] * accel[i, c] if free[i] else 0.0
            diag[i, c] = mass[i] * dm if free[i] else 1.0
    for e in range(edges.shape[0]):
        a = edges[e, 0]
        b = edges[e, 1]
        nx = dirs[e, 0]
        ny = dirs[e, 1]
        nz = dirs[e, 2]
        s = tension[e]
        # h² (K v)_a = −h² k [n nᵀ + s (I − n nᵀ)] (v_a − v_b)
        wx, wy, wz = _spring_block_product(v, a, b, nx, ny, nz, s, ck, 0.0)
        dxx = ck * (s + (1.0 - s) * nx * nx) + cd * nx * nx
        dyy = ck * (s + (1.0 - s) * ny * ny) + cd * ny * ny
        dzz = ck * (s + (1.0 - s) * nz * nz) + cd * nz * nz
        if free[a]:
            r[a, 0] -= wx
            r[a, 1] -= wy
            r[a, 2] -= wz
            diag[a, 0] += dxx
            diag[a, 1] += dyy
            diag[a, 2] += dzz
        if free[b]:
            r[b, 0] += wx
            r[b, 1] += wy
            r[b, 2] += wz
            diag[b, 0] += dxx
            diag[b, 1] += dyy
            diag[b, 2] += dzz
    # CG warm-started from the previous substep's Δv (accelerations change little from one
    # substep to the next): r = b − A Δv
    bnorm2 = 0.0
    finite = True
    for i in range(n):
        for c in range(3):
            bnorm2 += r[i, c] * r[i, c]
            finite = finite and math.isfinite(dv[i, c])
    if bnorm2 == 0.0 or not finite:
        dv[...] = 0.0
    dmass = mass * dm
    _apply_system(dv, q, edges, dirs, tension, dmass, free, ck, cd)
    rz = 0.0
    for i in range(n):
        for c in range(3):
            if not free[i]:
                dv[i, c] = 0.0
            r[i, c] -= q[i, c] if free[i] else 0.0
            z[i, c] = r[i, c] / diag[i, c]
            p[i, c] = z[i, c]
            rz += r[i, c] * z[i, c]
    it = 0
    if bnorm2 > 0.0:
        stop2 = tol * tol * bnorm2
        rr = 0.0
        for i in range(n):
            for c in range(3):
                rr += r[i, c] * r[i, c]
        while it < max_iter and rr > stop2:
            _apply_system(p, q, edges, dirs, tension, dmass, free, ck, cd)
            pq = 0.0
            for i in range(n):
                for c in range(3):
                    pq += p[i, c] * q[i, c]
            if pq <= 0.0:
                break
            alpha = rz / pq
            rr = 0.0
            for i in range(n):
                for c in range(3):
                    dv[i, c] += alpha * p[i, c]
                    r[i, c] -= alpha * q[i, c]
                    rr += r[i, c] * r[i, c]
            it += 1
            if rr <= stop2:
                break
            rz_new = 0.0
            for i in range(n):
                for c in range(3):
                    z[i, c] = r[i, c] / diag[i, c]
                    rz_new += r[i, c] * z[i, c]
            beta = rz_new / rz
            rz = rz_new
            for i in range(n):
                for c in range(3):
                    p[i, c] = z[i, c] + beta * p[i, c]
    for i in range(n):
        if free[i]:
            for c in range(3):
                v[i, c] += dv[i, c]
                x[i, c] += h * v[i, c]
    return it


@njit(nogil=True, cache=True, fastmath=True)
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


# --- effects ----------------------------------------------------------------------------------

class _StateView:
    """What a force effect's `apply(state, h)` sees when adapted to `accumulate`."""
    __slots__ = ("x", "x_prev", "v", "accel", "anchors", "t", "steps")


def force_accumulator(effect, h: float):
    """`accumulate(x, v, t, out_accel)` of a force effect; adapts `apply(state, h)` (which must
    only add to state.accel) for effects that do not have it."""
    if hasattr(effect, "accumulate"):
        return effect.accumulate
    view = _StateView()
    view.steps = 0
    view.anchors = None

    def accumulate(x, v, t, out_accel):
        view.x, view.x_prev, view.v, view.accel, view.t = x, x, v, out_accel, t
        effect.apply(view, h)

    return accumulate


def is_kinematic(effect) -> bool:
    """An effect that drives the state directly (forces.Wave moves the pins' anchors) rather
    than only adding acceleration: its `apply` runs once per substep before integrating."""
    return bool(getattr(effect, "kinematic", type(effect).__name__ == "Wave"))


class IntegrateSprings:
    """One substep of the spring system with the chosen integrator. Named after it
    (integrate_rk4, integrate_implicit_euler, ...). Sets x_prev to the start positions and
    leaves the integrator's end positions in `x_pred` for `correct_velocities`."""

    def __init__(self, model, behavior, force_effects: list, h: float):
        self.integrator = integrator_for(behavior)  # `auto` resolved for springs
        if self.integrator not in ORDERS:
            raise ValueError(f"unknown integrator {self.integrator!r}")
        self.name = f"integrate_{self.integrator}"
        self.model = model
        self.k = float(behavior.stiffness)
        self.kd = float(behavior.spring_damping)
        self.drag = drag_rate(behavior.damping)
        self.forces = [force_accumulator(f, h) for f in force_effects]
        # Kinematic drives (the wave moves pin anchors) still run once per substep, as with pbd.
        self.kinematic = [f for f in force_effects if is_kinematic(f)]
        self.cg_iterations = 0
        n = model.num_particles
        z = lambda: np.zeros((n, 3))  # noqa: E731
        self.x_pred = z()
        self._a = [z() for _ in range(4)]
        self._xs, self._vs, self._vt = z(), z(), z()
        self._free = np.asarray(model.inv_mass != 0.0)
        if self.integrator == "implicit_euler":
            m = max(1, model.num_constraints)
            self._dirs = np.zeros((m, 3))
            self._tension = np.zeros(m)
            self._cg = [z() for _ in range(5)]

    def accel(self, x, v, t, out):
        """out = a(x, v, t): external forces, springs, drag; zero on pinned particles."""
        out.fill(0.0)
        for f in self.forces:
            f(x, v, t, out)
        m = self.model
        add_spring_accel(x, v, m.edges, m.rest_length, m.inv_mass, self.k, self.kd,
                         self.drag, out)
        zero_rows(out, m.pinned)
        return out

    def apply(self, state, h):
        x, v, t = state.x, state.v, state.t
        for effect in self.kinematic:
            effect.apply(state, h)
        state.x_prev[...] = x
        getattr(self, "_" + self.integrator)(x, v, t, h)
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
        dv, r, z, p, q = self._cg
        self.cg_iterations = solve_implicit_euler(
            x, v, a, m.mass, self._free, m.edges, m.rest_length, self.k, self.kd, self.drag,
            h, self._dirs, self._tension, dv, r, z, p, q, self._a[1], CG_TOLERANCE,
            CG_MAX_ITERATIONS)


class CorrectVelocities:
    name = "correct_velocities"

    def __init__(self, model, integrate: IntegrateSprings, max_speed: float):
        self.inv_mass = model.inv_mass
        self.integrate = integrate
        self.max_speed = max_speed

    def apply(self, state, h):
        finish_velocities(state.x, state.x_prev, self.integrate.x_pred, state.v, self.inv_mass,
                          1.0 / h, self.max_speed)


def assemble(scene, model, h: float, force_effects: list, contact_effects: list) -> list:
    """integrate_<integrator> (forces and springs inside) → contacts → (tethers) → pins →
    velocities."""
    b = scene.behavior
    integrate = IntegrateSprings(model, b, force_effects, h)
    effects = [integrate]
    effects += contact_effects
    if getattr(model, "tether_pin", None) is not None and hasattr(solvers, "EnforceTethers"):
        effects.append(solvers.EnforceTethers(model))  # a position projection, like contacts
    if len(model.pinned):
        effects.append(solvers.ApplyPins(model))
    effects.append(CorrectVelocities(model, integrate, b.max_speed))
    return effects
