"""The force-based solver: Hooke springs advanced by a chosen integrator (integrators.py).
The integrator evaluates the springs and the force effects itself; there is no constraint
stage; velocities are the integrator's except where a contact or pin moved a particle.
Stiffness, damping and the speed limit are read from `params` each substep."""

from __future__ import annotations

from ...run.measures import spring_energy
from ...params import StepParams
from ...protocols import Effect, ForceEffect
from ..base import SolverBase
from .integrators import CorrectVelocities, IntegrateSprings

# An unconditionally stable integrator: an unstable step cannot be what stretched the sheet.
STABLE_AT_ANY_STEP = ("implicit_euler",)


class SpringSolver(SolverBase):
    name = "springs"
    watches_energy = True

    def __init__(self, model, behavior, forces: list[ForceEffect], h: float,
                 params: StepParams):
        super().__init__(model, behavior, forces, h, params)
        self.integrator = IntegrateSprings(model, behavior, forces, params)
        self._velocities = CorrectVelocities(model, self.integrator, params)

    def retune(self, params: StepParams, model) -> None:
        """Nothing to remake: every number, and the model's masses, are read as they run."""
        self.model = model

    def integrate(self) -> list[Effect]:
        return [self.integrator]

    def velocities(self) -> Effect:
        return self._velocities

    @property
    def may_overstretch_unstably(self) -> bool:
        """An explicit integrator going unstable shows first as stretch (its speeds are
        clamped); implicit Euler may stretch a soft sheet far and be right."""
        return self.integrator.integrator not in STABLE_AT_ANY_STEP

    @property
    def damps_unaccounted(self) -> bool:
        return self.params.spring_damping > 0.0

    def solve_error(self, state) -> None:
        """None: Hooke springs stretch as their stiffness says, whatever the substeps."""
        return None

    def elastic_energy(self, state) -> float:
        """Σ ½ k (L − L0)² over the intact springs."""
        m = self.model
        if not m.num_constraints:
            return 0.0
        return float(spring_energy(state.x, m.edges, m.rest_length, state.alive,
                                   self.params.stiffness))

    def halt_advice(self) -> str:
        advice = "lower behavior.stiffness or raise behavior.substeps"
        if self.integrator.integrator not in STABLE_AT_ANY_STEP:
            advice += ", or use behavior.integrator = implicit_euler (stable at any step)"
        return advice
