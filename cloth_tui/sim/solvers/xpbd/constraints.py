"""Distance constraints in XPBD form (Macklin, Müller, Chentanez 2016); PBD is α = 0.

Each distance constraint C = |x_b − x_a| − L0 has compliance α (m/N, the inverse of a spring
stiffness). Per substep h, with α̃ = α/h² and a multiplier λ per constraint reset to 0 at the
start of the substep, every pass of coloured Gauss-Seidel does

    Δλ = (−C − α̃ λ) / (w_a + w_b + α̃),   λ += Δλ,   x_a −= w_a Δλ n,   x_b += w_b Δλ n

(n = (x_b − x_a)/|x_b − x_a|, w = inverse masses). The iteration converges to the implicit
Euler step of the elastic energy C²/(2α), so the material's stiffness is 1/α whatever the
number of iterations or the timestep. With α = 0 the update is PBD's projection exactly
(Δx = −w C n / (w_a + w_b)), which instead gets stiffer with more iterations and smaller
steps: one kernel serves both solvers (Ten Minute Physics' form).

A material (sim/fabric.py) gives each constraint its own α from the fabric and the edge's
rest geometry: then α̃ is an array, in the reference loop (`project_constraints_per_edge`)
and in the sweeps alike; a scene without one keeps the scalar path unchanged.
"""

from __future__ import annotations

import math

import numpy as np

from ...grid_sweeps import (COINCIDENT, NO_SLOT_ALPHAS, coincident_direction, plan_sweeps,
                          slot_alphas, sweep, sweep_grid_colors, sweep_grid_colors_parallel)
from ...jit import kernel
from ...threads import KernelChoice

# Below this many constraints per colour, thread start-up costs more than it saves.
PARALLEL_MIN_PER_COLOR = 4096


@kernel(inline="always")
def _project_one(x, inv_mass, a, b, rest, lam, alpha_t):
    """Projects one constraint; returns its Δλ."""
    wa = inv_mass[a]
    wb = inv_mass[b]
    if wa + wb == 0.0:
        return 0.0
    dx = x[b, 0] - x[a, 0]
    dy = x[b, 1] - x[a, 1]
    dz = x[b, 2] - x[a, 2]
    d2 = dx * dx + dy * dy + dz * dz
    if d2 < COINCIDENT * COINCIDENT:  # no direction of their own: grid_sweeps' fixed one
        dx, dy, dz = coincident_direction(a, b)
        d2 = COINCIDENT * COINCIDENT
    d = math.sqrt(d2)
    s = (rest - d - alpha_t * lam) / (d * (wa + wb + alpha_t))  # Δλ/d: one division
    x[a, 0] -= wa * s * dx
    x[a, 1] -= wa * s * dy
    x[a, 2] -= wa * s * dz
    x[b, 0] += wb * s * dx
    x[b, 1] += wb * s * dy
    x[b, 2] += wb * s * dz
    return s * d


@kernel()
def project_constraints(x, inv_mass, edges, rest, alive, color_offsets, lam, alpha_t,
                        iterations):
    """`iterations` passes of coloured Gauss-Seidel (edges are sorted by colour), serial;
    torn constraints (alive[e] == 0) are skipped.
    λ is reset here: it accumulates over the passes of one substep only. With α = 0 (PBD)
    λ does not enter the update and is not kept (lam stays 0, as the rigid limit has no
    elastic energy): its loads and stores cost ~15 % of the kernel's time."""
    lam[:] = 0.0
    for _ in range(iterations):
        if alpha_t == 0.0:
            for e in range(edges.shape[0]):
                if alive[e]:
                    _project_one(x, inv_mass, edges[e, 0], edges[e, 1], rest[e], 0.0, 0.0)
        else:
            for e in range(edges.shape[0]):
                if alive[e]:
                    lam[e] += _project_one(x, inv_mass, edges[e, 0], edges[e, 1], rest[e],
                                           lam[e], alpha_t)


@kernel()
def project_constraints_per_edge(x, inv_mass, edges, rest, alive, lam, alpha_t, iterations,
                                 fresh):
    """`project_constraints` with α̃ = alpha_t[e] per constraint (edges in colour order, as
    there). `fresh` = False goes on with λ of the last call (the same substep)."""
    if fresh:
        lam[:] = 0.0
    for _ in range(iterations):
        for e in range(edges.shape[0]):
            if alive[e]:
                lam[e] += _project_one(x, inv_mass, edges[e, 0], edges[e, 1], rest[e], lam[e],
                                       alpha_t[e])


class ProjectConstraints:
    """Projects the constraints with grid_sweeps' colour sweeps, on one thread or two as
    threads.KernelChoice measures best now. `project_constraints` above is the same update
    as a plain loop over model.edges: the reference the sweeps are tested against, and the
    bench's serial peer.

    `lambdas` holds the multipliers λ of the last substep, N·s², one per constraint in
    model.edges order (the constraint force is λ/h²); zero for PBD (α = 0), which does not
    keep them (the sweeps write PBD's into a scratch array). `compliance` is one α (m/N) for
    every constraint, or an array of one per constraint (a material's); `alpha_tilde` is
    α/h² as given, a float or that array."""

    def __init__(self, model, iterations: int, compliance, h: float, name: str):
        self.name = name
        self.model = model
        self.iterations = iterations
        self.lambdas = np.zeros(model.num_constraints)
        self._plan = plan_sweeps(model.nx, model.nz, model.edges, model.color_offsets,
                                 model.rest_length, model.inv_mass)
        self._scratch = self._plan.scratch()
        self.set_compliance(compliance, h)
        per_color = model.num_constraints / max(1, len(model.color_offsets) - 1)
        self.kernels = KernelChoice(
            sweep_grid_colors,
            sweep_grid_colors_parallel if per_color >= PARALLEL_MIN_PER_COLOR else None)

    def set_compliance(self, compliance, h: float) -> None:
        """α (m/N) for every constraint alike, or an array of one per constraint, at
        substeps of h; the sweep plan and the kernel choice stay."""
        per_edge = np.ndim(compliance) > 0
        self.alpha_t = np.asarray(compliance, dtype=np.float64) / (h * h) if per_edge \
            else compliance / (h * h)
        self._alpha_slots = slot_alphas(self._plan, self.alpha_t) if per_edge \
            else NO_SLOT_ALPHAS

    def refresh_masses(self) -> None:
        """Take the model's inverse masses again (written in place: model.refitted)."""
        self._plan.inv_mass[self._plan.grid_offset] = self.model.inv_mass

    @property
    def kernel_name(self) -> str:
        return self.kernels.kernel_name

    @property
    def threads(self) -> int:
        return self.kernels.threads

    @property
    def alpha_tilde(self):
        return self.alpha_t

    def apply(self, state, h):
        self.project(state, self.iterations, fresh=True)

    @property
    def slot_lambdas(self) -> tuple[np.ndarray, np.ndarray]:
        """(λ in the sweeps' slot order, the slot of each constraint): the live multipliers
        of a substep between `project` calls with fresh = False, for a correction of them
        (hpbd/multiplier_levels.py) that the next passes go on from."""
        return self._scratch.lam, self._plan.edge_slot

    def project(self, state, iterations: int, fresh: bool) -> None:
        """`iterations` passes; `fresh` starts the substep's λ at 0, False goes on with them."""
        alpha_t = 0.0 if self._alpha_slots.shape[0] else self.alpha_t
        sweep(self.kernels, self._plan, self._scratch, state.x, state.alive, self.lambdas,
              alpha_t, iterations, self._alpha_slots, fresh)
