"""Builds the step from a Scene: only the effects the scene enables, in the original's order.

The order of a substep's stages lives here and only here (`assemble`):
    solver.integrate()      forces, then the prediction (PBD/XPBD), or the integrator with
                            the forces inside (springs)
    contacts                colliders, then self-collision
    enforce_tethers         (if the model has tethers)
    solver.constraints()    the constraint projection (none for springs), then
    resolve_contacts        re-projection of what the constraints pulled into an object
    tear_constraints        (behavior.tear) overstretched constraints break, or with a
    / tear_by_strength      material's tear_strength overloaded ones (tearing.py)
    contact_friction        Coulomb friction on the contacts' whole substep motion
    contacts_after_friction each collider once more: out of what friction slid it into
    apply_pins, then soft_pins (pins.py; move_pins, first, moves keyed anchors)
    contacts_after_soft_pins each collider once more, where soft pins pulled (colliders.py)
    solver.velocities()
A scene without wind has no wind effect, so it runs no wind code. Effects, force effects and
colliders are the Protocols of protocols.py; solvers are SolverBase subclasses found through
the registry (solvers/registry.py). The stages read their numbers
(strengths, friction, damping, α) from the step's `params` (params.py): changing those is
`Step.retune`, not a new step.
"""

from __future__ import annotations

from dataclasses import dataclass, field
from typing import TYPE_CHECKING

import numpy as np

from .collision import colliders, selfcollision
from .effects import forces, impulses, tearing
from .model import ClothModel
from .params import StepParams
from .effects.pins import pin_effects
from .protocols import Collider, Effect, ForceEffect
from .solvers import SolverBase, registry
from .effects.stages import ApplyPins, EnforceTethers

if TYPE_CHECKING:
    from ..scene import Scene


@dataclass
class Step:
    model: ClothModel
    effects: list[Effect]
    substeps: int
    h: float                        # substep length, s
    colliders: list[Collider] = field(default_factory=list)
    frame_effects: list[Effect] = field(default_factory=list)  # once per frame, first
    solver: SolverBase | None = None  # None when integration is off
    params: StepParams = field(default_factory=StepParams)  # what the stages read

    def retune(self, scene: Scene, model: ClothModel) -> None:
        """Run on with `scene`'s parameters, a scene of this step's structure
        (params.same_structure), and `model`, this step's model refitted to it
        (model.refitted): the next substep reads them."""
        self.params.assign(scene)
        self.model = model
        if self.solver is not None:
            self.solver.retune(self.params, model)

    @property
    def names(self) -> list[str]:
        return [e.name for e in self.frame_effects] + [e.name for e in self.effects]

    def substep(self, state) -> None:
        h = self.h
        for effect in self.effects:
            effect.apply(state, h)
        state.t += h
        state.steps += 1

    def frame(self, state) -> None:
        if not self.effects:
            return  # integration off: the sheet is frozen, as in the original
        if self.frame_effects:
            before = state.x.copy()
            for effect in self.frame_effects:
                effect.apply(state, self.h * self.substeps)
            # an impulse moves particles outside the substeps (a raindrop displaces its
            # particle at once): its paths are swept like a substep's, so none goes through
            for collider in self.colliders:
                collider.sweep(state, before)
        for _ in range(self.substeps):
            self.substep(state)

    def penetration(self, x: np.ndarray) -> float:
        return max((c.penetration(x) for c in self.colliders), default=0.0)


def make_solver(scene: Scene, model: ClothModel, h: float, force_effects: list[ForceEffect],
                params: StepParams) -> SolverBase:
    """The scene's solver, as the registry names it."""
    solver_class = registry.spec(scene.behavior.solver).solver_class()
    return solver_class(model, scene.behavior, force_effects, h, params)


def tear_stage(scene: Scene, model: ClothModel, solver: SolverBase) -> Effect:
    """By the material's strength where it has one and the solver keeps the multipliers its
    constraints pull with (their forces), else by behavior.tear_stretch (tearing.py)."""
    strength = tearing.tear_strength(scene.behavior, model)
    if strength is not None and solver.lambdas is not None:
        return tearing.TearByStrength(model, solver.lambdas, strength,
                                      model.fabric.material.tear_length)
    return tearing.TearConstraints(model, scene.behavior.tear_stretch)


def assemble(solver: SolverBase, model: ClothModel, collider_effects: list[Collider],
             contact_effects: list[Effect], tear: Effect | None = None) -> list[Effect]:
    """The substep's stages, in order (see the module's docstring)."""
    move_pins, soft_pins = pin_effects(model)
    effects = move_pins + list(solver.integrate())
    effects += contact_effects
    if model.tether_pin is not None:
        # Before the constraints, which then smooth the tether's pull into the sheet: on a
        # 128² sheet this gives 0.44 max stretch against 1.5 with tethers after them.
        effects.append(EnforceTethers(model))
    constraints = solver.constraints()
    if constraints:
        effects += constraints
        if collider_effects:
            effects.append(colliders.ResolveContacts(collider_effects))
    if tear is not None:
        effects.append(tear)  # on the solved lengths: what the solve could not hold breaks
    if collider_effects:
        # on the substep's whole motion, constraints included (see colliders.py)
        effects.append(colliders.ContactFriction(collider_effects))
        effects.append(colliders.ContactsAfterFriction(collider_effects))
    if len(model.pinned):
        effects.append(ApplyPins(model))
    effects += soft_pins
    if soft_pins and collider_effects:
        # contacts win over soft attachments: a target inside an object drags no particle in
        effects.append(colliders.ContactsAfterSoftPins(collider_effects))
    effects.append(solver.velocities())
    return effects


def build(scene: Scene, model: ClothModel, substeps: int | None = None) -> Step:
    """The step for `scene`. `substeps` overrides the scene's (used by the numerical guard)."""
    b = scene.behavior
    n_sub = substeps or b.substeps
    h = 1.0 / (b.frame_rate * n_sub)
    params = StepParams.of(scene)
    if not scene.forces.integrate:
        return Step(model, [], n_sub, h, params=params)
    solver = make_solver(scene, model, h, forces.build_forces(scene, model, params), params)
    collider_effects = colliders.build_colliders(scene, model, params)
    contact_effects = collider_effects + selfcollision.build_self_collision(scene, model)
    tear = tear_stage(scene, model, solver) if b.tear and model.num_constraints else None
    effects = assemble(solver, model, collider_effects, contact_effects, tear)
    return Step(model, effects, n_sub, h, colliders=collider_effects,
                frame_effects=impulses.build_impulses(scene, model, params), solver=solver,
                params=params)
