"""XPBD: compliant position-based constraints (Macklin, Müller, Chentanez 2016).

Each distance constraint C = |x_b − x_a| − L0 has compliance α = behavior.compliance (m/N,
the inverse of a spring stiffness). Per substep h, with α̃ = α/h² and a multiplier λ per
constraint reset to 0 at the start of the substep, every pass of coloured Gauss-Seidel does

    Δλ = (−C − α̃ λ) / (w_a + w_b + α̃),   λ += Δλ,   x_a −= w_a Δλ n,   x_b += w_b Δλ n

(n = (x_b − x_a)/|x_b − x_a|, w = inverse masses). The iteration converges to the implicit
Euler step of the elastic energy C²/(2α), so the material's stiffness is 1/α whatever the
number of iterations or the timestep; PBD (α = 0, no λ) instead gets stiffer with more
iterations and smaller steps. α = 0 gives rigid constraints (XPBD then equals PBD).

The rest of the substep is the PBD solver's: verlet prediction with damping, contacts,
projection, pins, v = (x − x_prev)/h.
"""

from __future__ import annotations

import math

import numpy as np
from numba import njit, prange

from . import colliders, solvers


@njit(nogil=True, cache=True, fastmath=True)
def _project_range(x, inv_mass, edges, rest, lam, alpha_t, lo, hi):
    """One Gauss-Seidel pass over constraints [lo, hi). (Written out in one loop: a helper
    called per constraint made the kernel 3× slower.)"""
    for e in range(lo, hi):
        a = edges[e, 0]
        b = edges[e, 1]
        wa = inv_mass[a]
        wb = inv_mass[b]
        w = wa + wb + alpha_t
        if wa + wb == 0.0:
            continue
        dx = x[b, 0] - x[a, 0]
        dy = x[b, 1] - x[a, 1]
        dz = x[b, 2] - x[a, 2]
        d2 = dx * dx + dy * dy + dz * dz
        if d2 < 1e-24:
            continue
        d = math.sqrt(d2)
        dlam = (rest[e] - d - alpha_t * lam[e]) / w
        lam[e] += dlam
        s = dlam / d
        x[a, 0] -= wa * s * dx
        x[a, 1] -= wa * s * dy
        x[a, 2] -= wa * s * dz
        x[b, 0] += wb * s * dx
        x[b, 1] += wb * s * dy
        x[b, 2] += wb * s * dz


@njit(nogil=True, cache=True, fastmath=True)
def project_xpbd_constraints(x, inv_mass, edges, rest, color_offsets, lam, alpha_t, iterations):
    """`iterations` passes of coloured Gauss-Seidel (edges are sorted by colour), serial.
    λ is reset here: it accumulates over the passes of one substep only."""
    for e in range(lam.shape[0]):
        lam[e] = 0.0
    for _ in range(iterations):
        _project_range(x, inv_mass, edges, rest, lam, alpha_t, 0, edges.shape[0])


@njit(nogil=True, cache=True, fastmath=True, parallel=True)
def project_xpbd_constraints_parallel(x, inv_mass, edges, rest, color_offsets, lam, alpha_t,
                                      iterations):
    """Same projection; the constraints of one colour share no particle, so a colour is split
    across threads (in blocks) without races."""
    for e in prange(lam.shape[0]):
        lam[e] = 0.0
    block = 1024
    for _ in range(iterations):
        for c in range(color_offsets.shape[0] - 1):
            lo = color_offsets[c]
            hi = color_offsets[c + 1]
            nb = (hi - lo + block - 1) // block
            for k in prange(nb):
                _project_range(x, inv_mass, edges, rest, lam, alpha_t, lo + k * block,
                               min(hi, lo + (k + 1) * block))


class ProjectXPBDConstraints:
    name = "project_xpbd_constraints"

    def __init__(self, model, compliance: float, iterations: int, h: float):
        self.model = model
        self.iterations = iterations
        self.alpha_t = compliance / (h * h)
        self.lam = np.zeros(model.num_constraints)  # λ of the current substep, N·s²
        per_color = model.num_constraints / max(1, len(model.color_offsets) - 1)
        self.kernel = (project_xpbd_constraints_parallel
                       if per_color >= solvers.PARALLEL_MIN_PER_COLOR
                       else project_xpbd_constraints)

    def apply(self, state, h):
        m = self.model
        self.kernel(state.x, m.inv_mass, m.edges, m.rest_length, m.color_offsets, self.lam,
                    self.alpha_t, self.iterations)


def assemble(scene, model, h: float, force_effects: list, contact_effects: list) -> list:
    """forces → integrate_verlet → contacts → (tethers) → project_xpbd_constraints → pins →
    velocities."""
    b = scene.behavior
    effects = list(force_effects)
    effects.append(solvers.IntegrateVerlet(model, b.damping, h, b.max_speed))
    effects += contact_effects
    if getattr(model, "tether_pin", None) is not None and hasattr(solvers, "EnforceTethers"):
        effects.append(solvers.EnforceTethers(model))  # as in pbd: before the constraints
    if model.num_constraints:
        effects.append(ProjectXPBDConstraints(model, b.compliance, b.iterations, h))
        effects += colliders.resolve_contacts(contact_effects)
    if len(model.pinned):
        effects.append(solvers.ApplyPins(model))
    effects.append(solvers.UpdateVelocities())
    return effects
