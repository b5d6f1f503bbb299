"""What the runner hands the accuracy control (substep_control.py) and the numerical-damping
meter (numerical_damping.py): the tolerance a scene asks, a frame's solve error, and the
energies a frame's damping is told from."""

from __future__ import annotations

from typing import TYPE_CHECKING

import numpy as np

from ..effects.tearing import strength_tolerance, tear_strength
from ..model import ClothModel
from ..state import ClothState
from .measures import free_energy, kinetic_energy, per_constraint, potential_floor, solve_error
from .numerical_damping import DampingMeter, asked_loss, touching

if TYPE_CHECKING:
    from ...scene import Scene
    from ..pipeline import Step


def error_tolerance(scene: Scene, model: ClothModel) -> float:
    """behavior.error_tolerance, or tighter where the sheet tears by strength: tight
    enough to know the tension to a tenth of the strength (tearing.strength_tolerance)."""
    tol = scene.behavior.error_tolerance
    strength = tear_strength(scene.behavior, model)
    return tol if strength is None else min(tol, strength_tolerance(model, strength))


class SolveError:
    """A frame's solve error (measures.solve_error), keeping α̃
    = α/h² per constraint (0 for rigid ones and springs) until the solver's changes (a
    measured fabric's edges take a new α each substep: sim/fabric/stretch_curve.py)."""

    def __init__(self):
        self._alpha_tilde: np.ndarray | None = None
        self._alpha_tilde_of = None

    def forget(self) -> None:
        """The step was rebuilt or retuned: α̃ may have changed."""
        self._alpha_tilde = None

    def alpha_tilde(self, model: ClothModel, step: Step) -> np.ndarray:
        solver = step.solver
        source = 0.0 if solver is None else solver.alpha_tilde
        if self._alpha_tilde is None or source is not self._alpha_tilde_of:
            self._alpha_tilde = per_constraint(source, model.num_constraints)
            self._alpha_tilde_of = source
        return self._alpha_tilde

    def measure(self, model: ClothModel, step: Step, state: ClothState) -> float:
        solver = step.solver  # pbd keeps a λ array too (zeros), so nothing is allocated
        lambdas = None if solver is None else solver.lambdas
        return solve_error(model, state.x, state.alive, lambdas, self.alpha_tilde(model, step))


def measure_damping(meter: DampingMeter, e_start: float | None, e_end, model: ClothModel,
                    good: ClothState, state: ClothState, scene: Scene, step: Step,
                    pin_distance, nearest_pin) -> None:
    """The numerical damping of the frame just run from `good` to `state`, where it can be
    told apart. `e_end()`: the sheet's energy now."""
    if e_start is None or state.torn != good.torn or touching(step.colliders, state.x):
        meter.unmeasured()
        return
    floor = potential_floor(model, good, scene, pin_distance, nearest_pin)
    if floor is None:
        meter.unmeasured()
        return
    asked = asked_loss(model, scene, step.h, step.substeps,
                       kinetic_energy(model, good), kinetic_energy(model, state))
    meter.end(e_start, e_end(), asked, free_energy(e_start, floor, model),
              1.0 / scene.behavior.frame_rate)
