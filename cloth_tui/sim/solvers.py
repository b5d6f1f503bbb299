"""Integrators and constraint projection: the kernels of the position-based step.

One substep of the PBD solver, as in the original (Ten Minute Physics reads the same way):
    integrate_verlet            x_prev ← x;  x ← x + (1−D)·v·h + a·h²
    (colliders, self-collision)
    project_distance_constraints  `iterations` coloured Gauss-Seidel passes
    apply_pins                  pinned particles back to their anchors
    update_velocities           v ← (x − x_prev)/h
All kernels are compiled with nogil so the simulation thread leaves the GIL to the UI.
"""

from __future__ import annotations

import math
import time

from numba import njit, prange

from ..scene import ORIGINAL_TIMESTEP
from . import colliders

# Below this many constraints per colour, thread start-up costs more than it saves.
PARALLEL_MIN_PER_COLOR = 4096


def damping_factor(damping: float, h: float) -> float:
    """Velocity kept per step of length h. `damping` is the share lost per 18 ms (the
    original's step), so the decay rate −ln(1−d)/0.018 s⁻¹ does not depend on the timestep."""
    return (1.0 - damping) ** (h / ORIGINAL_TIMESTEP)


@njit(nogil=True, cache=True, fastmath=True)
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


@njit(nogil=True, cache=True, fastmath=True, inline="always")
def _project_one(x, inv_mass, a, b, rest):
    wa = inv_mass[a]
    wb = inv_mass[b]
    w = wa + wb
    if w == 0.0:
        return
    dx = x[b, 0] - x[a, 0]
    dy = x[b, 1] - x[a, 1]
    dz = x[b, 2] - x[a, 2]
    d2 = dx * dx + dy * dy + dz * dz
    if d2 < 1e-24:
        # Coincident ends have no direction to separate along: pick one from the indices,
        # so a crushed sheet unfolds instead of staying collapsed.
        dx = math.sin(1.3 * a + 7.1 * b)
        dy = math.cos(3.7 * a - 1.9 * b)
        dz = math.sin(2.3 * a + 0.7 * b + 1.0)
        scale = 1e-12 / math.sqrt(dx * dx + dy * dy + dz * dz)
        dx *= scale
        dy *= scale
        dz *= scale
        d2 = 1e-24
    d = math.sqrt(d2)
    s = (d - rest) / (d * w)
    x[a, 0] += wa * s * dx
    x[a, 1] += wa * s * dy
    x[a, 2] += wa * s * dz
    x[b, 0] -= wb * s * dx
    x[b, 1] -= wb * s * dy
    x[b, 2] -= wb * s * dz


@njit(nogil=True, cache=True, fastmath=True)
def project_distance_constraints(x, inv_mass, edges, rest, color_offsets, iterations):
    """Coloured Gauss-Seidel projection of |xa − xb| = rest, mass-weighted, serial."""
    for _ in range(iterations):
        for k in range(edges.shape[0]):
            _project_one(x, inv_mass, edges[k, 0], edges[k, 1], rest[k])


@njit(nogil=True, cache=True, fastmath=True, parallel=True)
def project_distance_constraints_parallel(x, inv_mass, edges, rest, color_offsets, iterations):
    """Same projection; the constraints of one colour share no particle, so each colour is
    split across threads without races."""
    for _ in range(iterations):
        for c in range(color_offsets.shape[0] - 1):
            lo = color_offsets[c]
            for k in prange(lo, color_offsets[c + 1]):
                _project_one(x, inv_mass, edges[k, 0], edges[k, 1], rest[k])


@njit(nogil=True, cache=True, fastmath=True)
def apply_pins(x, pinned, anchors):
    for k in range(pinned.shape[0]):
        i = pinned[k]
        x[i, 0] = anchors[k, 0]
        x[i, 1] = anchors[k, 1]
        x[i, 2] = anchors[k, 2]


@njit(nogil=True, cache=True, fastmath=True)
def update_velocities(x, x_prev, v, inv_h):
    for i in range(x.shape[0]):
        v[i, 0] = (x[i, 0] - x_prev[i, 0]) * inv_h
        v[i, 1] = (x[i, 1] - x_prev[i, 1]) * inv_h
        v[i, 2] = (x[i, 2] - x_prev[i, 2]) * inv_h


class IntegrateVerlet:
    name = "integrate_verlet"

    def __init__(self, model, damping: float, h: float, max_speed: float):
        self.inv_mass = model.inv_mass
        self.keep = damping_factor(damping, h)
        self.max_speed = max_speed

    def apply(self, state, h):
        integrate_verlet(state.x, state.x_prev, state.v, state.accel, self.inv_mass, h,
                         self.keep, self.max_speed)


class ProjectConstraints:
    """Projects the constraints with the serial or the parallel kernel, whichever is faster
    now. Two threads win on an idle machine at large sheets; when the render and UI threads
    (or anything else) hold the other core, a parallel kernel waits at every colour's barrier
    and loses several times over. So the choice is measured, not assumed: the other kernel is
    re-timed every PROBE_EVERY calls."""

    name = "project_constraints"
    PROBE_EVERY = 64

    def __init__(self, model, iterations: int):
        self.model = model
        self.iterations = iterations
        per_color = model.num_constraints / max(1, len(model.color_offsets) - 1)
        self.kernels = [project_distance_constraints]
        if per_color >= PARALLEL_MIN_PER_COLOR:
            self.kernels.append(project_distance_constraints_parallel)
        self.cost = [0.0] * len(self.kernels)  # seconds per call, latest estimate
        self.choice = len(self.kernels) - 1
        self.calls = 0

    @property
    def kernel_name(self) -> str:
        return self.kernels[self.choice].__name__

    def apply(self, state, h):
        m = self.model
        args = (state.x, m.inv_mass, m.edges, m.rest_length, m.color_offsets, self.iterations)
        if len(self.kernels) == 1:
            self.kernels[0](*args)
            return
        self.calls += 1
        k = self.choice
        if self.calls % self.PROBE_EVERY == 0 or not all(self.cost):
            k = next((i for i, c in enumerate(self.cost) if not c), 1 - self.choice)
        t0 = time.perf_counter()
        self.kernels[k](*args)
        dt = time.perf_counter() - t0
        self.cost[k] = dt if k != self.choice or not self.cost[k] else 0.8 * self.cost[k] + 0.2 * dt
        self.choice = int(self.cost[1] < self.cost[0]) if all(self.cost) else self.choice


@njit(nogil=True, cache=True, fastmath=True)
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
        m = self.model
        enforce_tethers(state.x, m.pinned, state.anchors, m.tether_pin, m.tether_length)


class ApplyPins:
    name = "apply_pins"

    def __init__(self, model):
        self.pinned = model.pinned

    def apply(self, state, h):
        apply_pins(state.x, self.pinned, state.anchors)


class UpdateVelocities:
    name = "update_velocities"

    def apply(self, state, h):
        update_velocities(state.x, state.x_prev, state.v, 1.0 / h)


def assemble(scene, model, h: float, force_effects: list, contact_effects: list) -> list:
    """The substep's effects for the scene's solver:
    forces → integrate → contacts (colliders, self-collision) → constraints → pins → velocities.
    """
    b = scene.behavior
    if b.solver == "xpbd":
        from . import xpbd
        return xpbd.assemble(scene, model, h, force_effects, contact_effects)
    if b.solver == "springs":
        from . import springs
        return springs.assemble(scene, model, h, force_effects, contact_effects)
    effects = list(force_effects)
    effects.append(IntegrateVerlet(model, b.damping, h, b.max_speed))
    effects += contact_effects
    if model.tether_pin is not None:
        # Before the constraints, which then smooth the tether's pull into the sheet: on a
        # 128² sheet this gives 0.44 max stretch against 1.5 with tethers after them.
        effects.append(EnforceTethers(model))
    if model.num_constraints:
        effects.append(ProjectConstraints(model, b.iterations))
        effects += colliders.resolve_contacts(contact_effects)
    if len(model.pinned):
        effects.append(ApplyPins(model))
    effects.append(UpdateVelocities())
    return effects
