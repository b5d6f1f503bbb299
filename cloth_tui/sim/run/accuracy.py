"""What the runner hands the accuracy control (substep_control.py) and the numerical-damping
meter (numerical_damping.py): the tolerance a scene asks and the energies a frame's damping
is told from (a frame's solve error is its solver's: SolverBase.solve_error)."""

from __future__ import annotations

from typing import TYPE_CHECKING


from ..effects.tearing import strength_tolerance, tear_strength
from ..model import ClothModel
from ..state import ClothState
from .measures import free_energy, kinetic_energy, potential_floor
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
