"""What every solver is: a `SolverSpec` (its name and traits, declared in
cloth_tui/solver_specs.py where the scene schema reads them) and a `SolverBase` subclass (its
stages and what the runner, the measures and the guard ask of it).

A solver supplies three lists of stages, which pipeline.assemble puts in the substep's one
order: `integrate()` (the forces and the prediction, or an integrator with the forces
inside), `constraints()` (run after the contacts) and `velocities()` (last).
"""

from __future__ import annotations

from typing import TYPE_CHECKING

from ...solver_specs import SolverSpec

if TYPE_CHECKING:
    import numpy as np

    from ..params import StepParams
    from ..protocols import Effect, ForceEffect
    from ..state import ClothState

__all__ = ["SolverBase", "SolverSpec"]  # SolverSpec: for a solver declared at run time


class SolverBase:
    """A solver's stages and the numbers its callers read. Subclasses set `name` and build
    their stages in `__init__(model, behavior, forces, h, params)`.

    `lambdas`: the constraint multipliers of the last substep, N·s², one per model.edges
    constraint, or None where there are none (force-based); tearing by strength reads them.
    `alpha_tilde`: α/h² of those constraints, a float for all alike or one per constraint.
    `watches_energy`: a force-based integrator going unstable pumps energy in, so the
    divergence guard compares each frame's energy with its start in a scene with no source;
    `may_overstretch_unstably`: an unstable integrator shows first as stretch.
    `bounds_energy_made`: a solve stopped early can make energy that its solve error does
    not see, so the accuracy control bounds energy made even with no energy tolerance set
    (substep_control.ENERGY_MADE_TOLERANCE)."""
    name: str = ""
    watches_energy: bool = False
    bounds_energy_made: bool = False

    def __init__(self, model, behavior, forces: list[ForceEffect], h: float,
                 params: StepParams):
        self.model = model
        self.behavior = behavior
        self.h = h
        self.params = params

    # -- the stages ---------------------------------------------------------------------
    def integrate(self) -> list[Effect]:
        raise NotImplementedError

    def constraints(self) -> list[Effect]:
        return []

    def velocities(self) -> Effect:
        raise NotImplementedError

    def retune(self, params: StepParams, model) -> None:
        """Remake what the solver derived from the step's parameters (params.py) and the
        model's numbers (masses, a fabric's α: model.refitted) when they change; what its
        stages read directly, they read as they run."""

    # -- what callers read --------------------------------------------------------------
    @property
    def lambdas(self) -> np.ndarray | None:
        return None

    @property
    def alpha_tilde(self):
        return 0.0

    @property
    def passes_per_substep(self) -> float:
        """The constraint work of a substep in passes over the sheet's constraints."""
        return 0.0

    @property
    def may_overstretch_unstably(self) -> bool:
        return False

    @property
    def damps_unaccounted(self) -> bool:
        """Whether the solver takes energy by a damping of its own that the numerical
        damping's bookkeeping does not count as asked for (numerical_damping.measurable)."""
        return False

    def solve_error(self, state: ClothState) -> float | None:
        """How far the last frame ended from the step the solver aims at, as a share of
        rest length: what behavior.error_tolerance bounds, the accuracy control raising the
        substeps until it is met. By default the constraints' residual max |C + α̃λ|/L0
        (measures.solve_error; pbd's α̃ is 0, so its stretch). None, always, for a solver
        that leaves none to bound (springs stretch as their stiffness says, whatever the
        substeps): the control then keeps the scene's substeps."""
        from ..run.measures import solve_error  # (this module imports no numpy)
        return solve_error(self.model, state.x, state.alive, self.lambdas, self.alpha_tilde)

    def elastic_energy(self, state: ClothState) -> float:
        """J stored in the constraints by the solver's own force estimate."""
        return 0.0

    def halt_advice(self) -> str:
        """What to change when a frame diverges even at the guard's most substeps."""
        return "raise behavior.substeps, or weaken the forces (gravity, wind, custom fields)"
