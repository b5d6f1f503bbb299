"""The divergence guard's tests of a frame just run: not finite, energy gained from nowhere,
springs overstretched, or any untorn sheet running away (neighbours ten times their
spacing apart). The runner undoes such a frame and retries it with more substeps
(up to 2**MAX_GUARD_LEVEL times as many), or halts and says why."""

from __future__ import annotations

import math
from typing import TYPE_CHECKING

from ..model import ClothModel
from ..state import ClothState
from .measures import (
    all_finite,
    energy,
    gravitational_energy,
    grid_spread,
    kinetic_energy,
    stretch,
)

if TYPE_CHECKING:
    from ...scene import Scene
    from ..pipeline import Step

SPRING_DIVERGED = 1.0  # |L/L0 − 1| beyond which a springs integrator counts as diverged
# Beyond this any solver counts as diverged: grid neighbours ten times their rest spacing
# apart, in a sheet nothing has torn, are no fabric's, and no solve that converges holds them
# so. A position-based step whose round-off grows (a fabric without structural edges at one
# iteration) runs away while finite. (A torn sheet's pieces may fly apart: not checked.)
RUNAWAY_SPREAD = 10.0
# ... unless the same frame at twice the substeps ends this close to the same stretch: an
# unstable step's stretch collapses when h halves, a load's (a heavy sheet, pins, a wave, a
# moving object) stays.
STRETCH_CONVERGED = 0.1
# A force-based integrator going unstable pumps energy in. In a scene with no energy source
# (wind, fields, rain, a wave, moving objects or pins) a frame may not gain more than this
# share of the sheet's energy scale (M·g·size + its kinetic and elastic energy): damping,
# contacts and a stable integrator only lose energy, an unstable one gains it exponentially.
ENERGY_GAIN_DIVERGED = 0.05
# deeper in a skin than this (share of it, m of rounding), a contact will push: energy_scale
OVERLAP_SHARE, OVERLAP_SLACK = 1e-3, 1e-9
MAX_GUARD_LEVEL = 4  # a diverging frame is retried with up to 2**4 = 16× the substeps
GUARD_EASE_FRAMES = 60  # frames between tries of half the substeps while recovering


def finite(state: ClothState) -> bool:
    return all_finite(state.x, state.v)


def watches_energy(step: Step, sources: bool) -> bool:
    """Whether the energy-gain check applies: a force-based solver, no energy source."""
    solver = step.solver
    return solver is not None and solver.watches_energy and not sources


def energy_scale(model: ClothModel, state: ClothState, scene: Scene,
                 step: Step) -> tuple[float, float]:
    """(energy, scale) at the start of a frame, for the energy-gain check; no bound
    (inf) where a contact will push a particle out of a skin at depth/h, a gain that
    more substeps raise: growth from a source, not from the step."""
    internal = kinetic_energy(model, state) + step.solver.elastic_energy(state)
    g = scene.forces.gravity_strength if scene.forces.gravity else 0.0
    scale = float(model.mass.sum()) * g * model.extent + internal + 1e-12
    if overlapping(model, state, step.colliders):
        scale = math.inf
    return internal + gravitational_energy(model, state, scene), scale


def overlapping(model: ClothModel, state: ClothState, colliders) -> bool:
    """A free particle deeper in a skin than contacts leave one (placed or bumped there)."""
    free = model.inv_mass != 0.0
    return any(c.signed_distance(state.x)[free].min(initial=math.inf)
               < c.thickness * (1.0 - OVERLAP_SHARE) - OVERLAP_SLACK
               for c in colliders)


def max_stretch(model: ClothModel, state: ClothState) -> float:
    return stretch(model, state.x, state.alive)[0]


def frame_problem(model: ClothModel, state: ClothState, scene: Scene, step: Step,
                  e0: tuple[float, float] | None) -> str | None:
    """What is wrong with the frame just run, or None: not finite, an untorn sheet spread
    beyond RUNAWAY_SPREAD, or (a force-based solver, whose `watches_energy`) energy gained from
    nowhere or, for explicit integrators, a spring at over twice its rest length. Every
    solver clamps speeds to max_speed, so speed shows nothing. A position-based step may
    legitimately stretch a lot at few iterations, so only a runaway counts for it; a
    force-based integrator going unstable shows as energy or as stretch. The runner takes
    "overstretched" back where the same frame at twice the substeps stretches as much (a
    load, not a divergence), and "spread apart" where it spreads as far."""
    if not finite(state):
        return "not finite"
    solver = step.solver
    if solver is None:
        return None
    if not solver.watches_energy:
        runaway = state.torn == 0 and grid_spread(model, state.x) > RUNAWAY_SPREAD
        return "spread apart" if runaway else None
    if e0 is not None:
        e_start, scale = e0
        if energy(model, state, scene, solver) - e_start > ENERGY_GAIN_DIVERGED * scale:
            return "energy gained"
    if solver.may_overstretch_unstably and max_stretch(model, state) > SPRING_DIVERGED:
        return "overstretched"
    return None


def sheet_spread(model: ClothModel, state: ClothState) -> float:
    return grid_spread(model, state.x)


def load_measure(problem: str | None):
    """For a problem a load may cause as well as a divergence, the measure (model, state) ->
    float whose value stays at twice the substeps under a load (stretch_converged); None
    for the others."""
    return {"overstretched": max_stretch, "spread apart": sheet_spread}.get(problem)


def stretch_converged(s1: float, s2: float) -> bool:
    """Whether a frame's stretch `s1` stays (within STRETCH_CONVERGED) at twice the substeps
    (`s2`): a load's stretch stays, an unstable step's collapses."""
    return abs(s2 - s1) <= STRETCH_CONVERGED * s1


def halt_reason(step: Step) -> str:
    """Why stepping stops where even the most substeps the guard tries diverge."""
    return (f"the step diverges even at {step.substeps} substeps per "
            f"frame; {step.solver.halt_advice()}, then restart")
