"""lbfgs: each substep's implicit step, solved as the minimum of its objective
(step_energy.py) by L-BFGS preconditioned with a constant matrix P (step_matrix.py), whose
inverse one multigrid V-cycle stands for (multigrid.py).

One substep, top to bottom (pipeline.assemble interleaves contacts, tearing and pins):
    integrate    the force effects add to state.accel; integrate_verlet predicts
                 y = x + (1−D)·v·h + a·h² (xpbd's prediction), or with BDF2 (bdf2.py)
                 predict_bdf2 its y over a step of h' = 2h/3
    solve        from x = y, `iterations` L-BFGS steps on Φ(x) = |x − y|²_M/(2h'²) + E(x):
                 d = −H g (two loops over the last HISTORY pairs, H₀ = P⁻¹, the pairs kept
                 from substep to substep until P changes or a direction fails to
                 descend), x += t·d with t halved until Φ falls enough (Armijo); each
                 edge's λ then holds its force
    velocities   update_velocities: v ← (x − x_prev)/h (BDF2: v ← (x − x̂)/h')
Its minimum is implicit Euler's step on the material's own energy, so a solve run to
convergence rests at the fabric's equilibrium. One stopped early stops at a lower Φ on the
way there, near where it started in the directions P resists, and from y a sheet at rest must
undo its prediction's whole fall: where that fall is across the sheet, held by its bending,
it does not, and the lab's clamped strip at the default scene's settings creeps and rings
short of the elastica (docs/physics.md, lbfgs, "Where the solve starts"). With the pairs
carried over no two substeps solve alike either, so at few iterations the sheet never quite
comes to rest (the lab's clamped strip at 8 iterations jitters by ~1e-3·L, docs/accuracy.md;
the default scene at 32 cells moves at up to 3.9 cm/s). What stopping early
costs is numerical damping, on top of implicit Euler's own (tools/solver_lab/bench.py
measures both on an undamped sheet), and, the pairs learnt on earlier substeps, energy made
that the solve error does not see: the accuracy control bounds that for this solver with no
tolerance set (`bounds_energy_made`; substep_control.py). BDF2, which damps what the
substeps resolve far less, is the step with behavior.integrator = "bdf2", or "auto" where
the scene bounds numerical damping (behavior.energy_tolerance).

The frame's solve error (`LBFGSSolver.solve_error`, which the accuracy control bounds) is how
far the solve still had to go when it stopped (`SolveImplicitStep.distance_left`) over the
shortest rest length: λ here is the solved step's force, so xpbd's error |C + α̃λ| would
read zero whatever the solve.
"""

from __future__ import annotations

import numpy as np

from ...params import StepParams
from ...protocols import Effect, ForceEffect
from ..base import SolverBase
from ..xpbd.verlet import IntegrateVerlet, UpdateVelocities
from .step_energy import (
    dot,
    edge_multipliers,
    first_loop,
    second_loop,
    step_objective,
    step_to,
)
from .bdf2 import STEP_SHARE, PredictBDF2, VelocitiesBDF2
from .step_matrix import kept_preconditioner

# L-BFGS pairs kept. They carry over from substep to substep, so older ones describe the
# objective of a sheet that has since moved; more pairs cost substeps where the sheet whips
# (measured in docs/physics.md, lbfgs).
HISTORY = 3
ARMIJO = 1e-4      # sufficient decrease of a line search step
HALVINGS = 8       # a step halved this often without enough decrease ends the substep's solve
# The pairs carry on into the next substep (the objective's Hessian changes little between
# them): what P misses, the sheet's turning against its stiff springs, is learnt over
# several substeps instead of anew in each one's few iterations (without them a swinging
# strip's swing dies at the default settings: docs/physics.md).
REBUILD_AFTER_TEAR = 30  # substeps between rebuilding P while the sheet tears


def bdf2_for(behavior) -> bool:
    """Whether the substeps are BDF2 (bdf2.py), not implicit Euler: asked for, or `auto`
    where the scene bounds numerical damping."""
    return behavior.integrator == "bdf2" or (behavior.integrator == "auto"
                                             and behavior.energy_tolerance > 0)


class SolveImplicitStep:
    """The solve stage (module docstring). `lambdas` (N·s², model.edges order) are each
    edge's force of the solved step as an XPBD multiplier, for tearing by strength."""

    name = "solve_implicit_step"

    def __init__(self, model, iterations: int, compliance: float, step_share: float = 1.0):
        self.iterations = iterations
        self.step_share = step_share  # the implicit step's length over the substep's
        self._last_step = None  # the last iteration's move (or the one it could not take)
        self._beyond = 0.0  # how much farther its line's minimum lies, in moves
        self._h = None
        self._p_inverse = None
        self.lambdas = np.zeros(model.num_constraints)
        self.set_model(model, compliance)

    def set_model(self, model, compliance: float) -> None:
        """Take `model`'s masses and material (or, without one, α = `compliance` on every
        edge); P is made anew at the next substep."""
        self.model = model
        f = model.fabric
        n = model.num_particles
        if f is not None:
            self.k_edge = np.ascontiguousarray(1.0 / np.asarray(f.compliance, dtype=float))
            self.cells = f.cells
            self.k_cell = 1.0 / f.cell_compliance if f.num_cells else 0.0
            self.scale = 1.0 / (4 * f.grid.dx * f.grid.dz)
            self.cell_edges = f.cell_edges
        else:
            self.k_edge = np.full(model.num_constraints, 1.0 / max(compliance, 1e-12))
            self.cells = np.zeros((0, 4), np.int64)
            self.k_cell, self.scale = 0.0, 0.0
            self.cell_edges = np.zeros((0, 4), np.int64)
        if f is not None and f.stencils is not None:
            self.sten_p, self.sten_c = f.stencils.particles, f.stencils.coeffs
            self.k_sten = np.ascontiguousarray(1.0 / np.asarray(f.stencil_compliance))
            self.sten_edges = f.stencil_edges
        else:
            self.sten_p, self.sten_c = np.zeros((0, 4), np.int64), np.zeros((0, 4))
            self.k_sten = np.zeros(0)
            self.sten_edges = np.zeros((0, 4), np.int64)
        self.cell_alive = np.ones(len(self.cells), np.uint8)
        self.sten_alive = np.ones(len(self.k_sten), np.uint8)
        self.fixed = (model.inv_mass == 0).astype(np.uint8)
        self._y = np.zeros((n, 3))
        self._g = np.zeros((n, 3))
        self._g_new = np.zeros((n, 3))
        self._trial = np.zeros((n, 3))
        self._s = np.zeros((HISTORY, n, 3))
        self._yh = np.zeros((HISTORY, n, 3))
        self._sv = np.zeros((n, 3))
        self._yv = np.zeros((n, 3))
        self._rho = np.zeros(HISTORY)
        self._alphas = np.zeros(HISTORY)
        self._h = None  # P for the next substep
        self._count = 0
        self._order = np.zeros(HISTORY, np.int64)
        self._torn_built = 0
        self._since_built = 0

    def _prepare(self, state, h: float) -> None:
        m = self.model
        held_now = (m.inv_mass == 0).astype(np.uint8)
        torn_changed = state.torn != self._torn_built
        if torn_changed:
            self._mask_torn(state.alive)
        stale = (self._h != h or not np.array_equal(held_now, self.fixed)
                 or (torn_changed and self._since_built >= REBUILD_AFTER_TEAR))
        self._since_built += 1
        if not stale:
            # (the V-cycle is shared with any other step of this sheet and stiffness)
            self._p_inverse.set_step(h)
            return
        self.fixed = held_now
        self._h = h
        self._count = 0
        self.mass_h2 = np.ascontiguousarray(m.mass / (h * h))
        self._p_inverse = kept_preconditioner(m, self.k_edge * state.alive, self.k_sten, h)
        self._torn_built = state.torn
        self._since_built = 0

    def _mask_torn(self, alive: np.ndarray) -> None:
        """A cell or stencil across a torn edge leaves the energy with it."""
        intact = np.append(alive, 1).astype(bool)  # index −1 (no such edge) reads intact
        if len(self.cell_edges):
            self.cell_alive[:] = intact[self.cell_edges].all(axis=1)
        if len(self.sten_edges):
            self.sten_alive[:] = intact[self.sten_edges].all(axis=1)

    def objective(self, x, y, alive, grad, want_grad: bool) -> float:
        m = self.model
        return step_objective(x, y, self.mass_h2, m.inv_mass, m.edges, m.rest_length,
                              self.k_edge, alive, self.cells, self.cell_alive, self.k_cell,
                              self.scale, self.sten_p, self.sten_c, self.k_sten,
                              self.sten_alive, 1.0, grad, want_grad)

    def elastic_energy(self, x, alive) -> float:
        """J: E(x), the material's energy at x (y = x: the inertia term is zero, whatever
        masses it is given)."""
        m = self.model
        return step_objective(x, x, m.mass, m.inv_mass, m.edges, m.rest_length, self.k_edge,
                              alive, self.cells, self.cell_alive, self.k_cell, self.scale,
                              self.sten_p, self.sten_c, self.k_sten, self.sten_alive, 1.0,
                              self._g_new, False)

    def apply(self, state, substep: float):
        h = substep * self.step_share
        self._prepare(state, h)
        x, y, alive = state.x, self._y, state.alive
        y[...] = x
        g, g_new, trial = self._g, self._g_new, self._trial
        phi = self.objective(x, y, alive, g, True)
        count, order = self._count, self._order
        last = None
        beyond = 0.0
        for _ in range(self.iterations):
            beyond = 0.0
            q = g.copy()
            first_loop(q, self._s, self._yh, self._rho, order, count, self._alphas)
            d = self._p_inverse.solve(q)
            second_loop(d, self._s, self._yh, self._rho, order, count, self._alphas,
                        self.fixed)
            slope = dot(g, d)
            if not slope < 0.0:  # not a descent direction (or NaN): restart from P⁻¹ alone
                count = 0
                d = -self._p_inverse.solve(g)
                d[self.fixed.astype(bool)] = 0.0
                slope = dot(g, d)
                if not slope < 0.0:
                    last = d
                    break
            t = 1.0
            for _ls in range(HALVINGS):
                step_to(x, d, t, trial)
                phi_new = self.objective(trial, y, alive, g_new, True)
                if phi_new <= phi + ARMIJO * t * slope:
                    break
                t *= 0.5
            else:
                last = d
                break
            np.subtract(trial, x, out=self._sv)
            last = self._sv
            np.subtract(g_new, g, out=self._yv)
            sy = dot(self._sv, self._yv)
            # where the minimum along this move's line lies by the secant of Φ's slope on it,
            # in moves beyond where the move ended: about 0 where it found that minimum
            beyond = max(0.0, -dot(g_new, self._sv) / sy) if sy > 0.0 else 0.0
            if sy > 0.0:  # curvature seen: keep the pair (else the history stays as it is)
                if count < HISTORY:
                    slot = count
                    count += 1
                else:
                    slot = order[0]
                    order[:-1] = order[1:]
                order[count - 1] = slot
                self._s[slot] = self._sv
                self._yh[slot] = self._yv
                self._rho[slot] = 1.0 / sy
            x[...] = trial
            g, g_new = g_new, g
            phi = phi_new
        self._g, self._g_new = g, g_new
        self._last_step = last
        self._beyond = beyond
        self._count = count
        m = self.model
        # in the substep's own h²: the tearing stage reads λ/h² with it
        edge_multipliers(x, m.edges, m.rest_length, self.k_edge, alive, substep * substep,
                         self.lambdas)

    def distance_left(self) -> float:
        """m: the largest move of a particle in the last substep's last iteration (where its
        line search found no decrease, the move it asked for), times 1 + how many such moves
        farther on the minimum along the move's line lies (`_beyond`). A solve that stalls,
        its moves short where P resists the sheet's turning, moves little but has that
        minimum far ahead: the move alone read it as converged."""
        last = self._last_step
        if last is None:
            return 0.0
        return float(np.sqrt(np.einsum("ij,ij->i", last, last)).max()) * (1.0 + self._beyond)


class LBFGSSolver(SolverBase):
    name = "lbfgs"
    bounds_energy_made = True

    def __init__(self, model, behavior, forces: list[ForceEffect], h: float,
                 params: StepParams):
        super().__init__(model, behavior, forces, h, params)
        if bdf2_for(behavior):
            # a second-order step whose solve stops early can gain energy: the guard's check
            self.watches_energy = True
            predict = PredictBDF2(model, params)
            self._velocities: Effect = VelocitiesBDF2(model, params, predict)
            share = STEP_SHARE
        else:
            predict = IntegrateVerlet(model, params)
            self._velocities = UpdateVelocities(model, params)
            share = 1.0
        self._predict = predict
        self._integrate: list[Effect] = list(forces) + [predict]
        self.projection = SolveImplicitStep(model, params.iterations, params.compliance,
                                            step_share=share)
        self._constraints: list[Effect] = [self.projection]

    def retune(self, params: StepParams, model) -> None:
        self.model = model
        self._predict.retune(model)
        self.projection.iterations = params.iterations
        self.projection.set_model(model, params.compliance)

    def integrate(self) -> list[Effect]:
        return self._integrate

    def constraints(self) -> list[Effect]:
        return self._constraints

    def velocities(self) -> Effect:
        return self._velocities

    @property
    def passes_per_substep(self) -> float:
        return float(self.projection.iterations)

    @property
    def lambdas(self) -> np.ndarray:
        return self.projection.lambdas

    @property
    def alpha_tilde(self):
        return 1.0 / (self.projection.k_edge * self.h * self.h)

    def elastic_energy(self, state) -> float:
        return self.projection.elastic_energy(state.x, state.alive)

    def solve_error(self, state) -> float:
        """How far the solve still had to go when it stopped
        (SolveImplicitStep.distance_left) as a share of the shortest rest length."""
        return self.projection.distance_left() / self._shortest_rest

    @property
    def _shortest_rest(self) -> float:
        rest = self.model.rest_length
        return float(rest.min()) if len(rest) else 1.0
