"""The contracts between the step builder (pipeline.py) and what it assembles.

An Effect acts on the state once per substep (or once per frame). Force effects can also be
evaluated at any positions and velocities, for integrators that take several stages per
substep. Colliders are effects that also measure penetration and say where their object is.
A solver (solvers/base.py) supplies its own stages; the order they run in is
pipeline.assemble's alone.
"""

from __future__ import annotations

from dataclasses import dataclass
from typing import TYPE_CHECKING, Protocol

import numpy as np

if TYPE_CHECKING:
    from .state import ClothState


@dataclass(frozen=True)
class ObjectPose:
    """Where an object is now and what it is, for the renderer and a bake (a copy; never
    shared with the kernels): its shape's registered `type`, that shape's `parameters`
    (sim/shapes/base.py: a sphere's {"radius": r}, a mesh's {"surface": MeshSurface}, ...)
    and its centre, m."""
    type: str
    parameters: dict
    center: tuple


class Effect(Protocol):
    name: str

    def apply(self, state: ClothState, h: float) -> None:
        """Advance `state` over a step of length h, s (a substep, or a frame for impulses)."""


class ForceEffect(Effect, Protocol):
    """`apply` adds to state.accel at the state's time; `accumulate` adds the same
    acceleration for any x, v, t. A kinematic effect drives the state directly instead (the
    wave moves pin anchors): force-based solvers run its `apply` once per substep."""
    kinematic: bool

    def accumulate(self, x: np.ndarray, v: np.ndarray, t: float, out_accel: np.ndarray) -> None:
        ...


class Collider(Effect, Protocol):
    """`apply` is the contact projection (run after the prediction, and again after the
    constraints); it records each contact's depth and normal for `apply_friction`, which runs
    once per substep after the last projection and clears them."""
    depth: np.ndarray  # (N,) m: how far the object pushed each particle this substep

    def apply_friction(self, state: ClothState, h: float) -> None:
        ...

    def sweep(self, state: ClothState, start: np.ndarray) -> None:
        """Stop every particle whose move from `start` to state.x, made outside a substep
        (a frame's impulse), came into the object, on the side it came from."""

    def penetration(self, x: np.ndarray) -> float:
        """Deepest any free particle is inside the true surface, m."""

    def pose(self, t: float) -> ObjectPose | None:
        """Where the object is at time t, for the renderer; None if the renderer draws it
        from the scene itself (the floor)."""
