"""Builds the step from a Scene: only the effects the scene enables, in the original's order.

Per substep: forces → integrate → collisions → self-collision → constraints → pins →
velocities. An effect is any object with a `name` and `apply(state, h)`; colliders also
offer `penetration(x)`. A scene without wind has no wind effect, so it runs no wind code.
"""

from __future__ import annotations

from dataclasses import dataclass, field

from ..scene import Scene
from . import colliders, forces, impulses, selfcollision, solvers
from .model import ClothModel


@dataclass
class Step:
    model: ClothModel
    effects: list
    substeps: int
    h: float                        # substep length, s
    colliders: list = field(default_factory=list)
    frame_effects: list = field(default_factory=list)  # once per frame, before the substeps

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
        for effect in self.frame_effects:
            effect.apply(state, self.h * self.substeps)
        for _ in range(self.substeps):
            self.substep(state)

    def penetration(self, x) -> float:
        return max((c.penetration(x) for c in self.colliders), default=0.0)


def build(scene: Scene, model: ClothModel, substeps: int | None = None) -> Step:
    """The step for `scene`. `substeps` overrides the scene's (used by the numerical guard)."""
    b = scene.behavior
    n_sub = substeps or b.substeps
    h = 1.0 / (b.frame_rate * n_sub)
    if not scene.forces.integrate:
        return Step(model, [], n_sub, h)
    force_effects = forces.build_forces(scene, model)
    collider_effects = colliders.build_colliders(scene, model)
    contact_effects = collider_effects + selfcollision.build_self_collision(scene, model)
    effects = solvers.assemble(scene, model, h, force_effects, contact_effects)
    return Step(model, effects, n_sub, h, colliders=collider_effects,
                frame_effects=impulses.build_impulses(scene, model))
