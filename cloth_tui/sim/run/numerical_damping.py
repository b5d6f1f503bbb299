"""Numerical damping: the energy a frame loses that no key asked for, told apart from what
energy sources, contacts and the damping keys change, and averaged for the report.

A frame's numerical damping is

    d = (E_start − E_end − asked) / (F_start · Δt)      (1/s)

with E the sheet's energy (measures.energy: kinetic, gravitational and the solver's own estimate of
the elastic, a material's every constraint family included), `asked` the kinetic energy the damping
key took (behavior.damping, or a material's own rate, which replaces it), F_start the free energy at
the frame's start (its energy above the lowest it could reach, measures.free_energy) and Δt the
frame's length. It is measured only where nothing else moves energy in or out (`measurable`,
`touching`); the runner's substep control bounds its mean (substep_control.py) and the report is a
running average (`DampingMeter`). Plain Python over the compiled measures.
"""

from __future__ import annotations

from dataclasses import dataclass
from typing import TYPE_CHECKING

import numpy as np

from ..fabric.material import damping_factor as decay_factor
from ..model import ClothModel
from ..effects.stages import damping_factor

if TYPE_CHECKING:
    from ...scene import Scene

# A particle closer than this many skins to a collider may be in contact, whose friction and
# inelastic contacts lose energy the numerical damping must not be blamed for.
CONTACT_SKINS = 2.0
# The reported numerical damping is averaged over about this many frames (a swing's
# exchange of kinetic and potential energy is not exact frame by frame).
AVERAGE_FRAMES = 30


def measurable(scene: Scene, model: ClothModel, solver, stepping: bool, sources: bool,
               held: bool) -> bool:
    """Whether all the energy a frame loses is either asked for or numerical: it steps, no
    source adds any (`sources`), no self-contact, damping of the solver's own (the springs'
    spring_damping) or soft pin takes any, and the sheet's lowest reachable energy is
    bounded (`held` by pins, a floor, or no gravity)."""
    if sources or scene.behavior.self_collision != "off" or not stepping:
        return False
    if solver is not None and solver.damps_unaccounted:
        return False
    if model.pin_layout is not None and len(model.pin_layout.soft.index):
        return False
    return held or scene.scene.floor or not scene.forces.gravity


def touching(colliders, x: np.ndarray) -> bool:
    """Whether any particle is within CONTACT_SKINS skins of a collider."""
    return any(float(c.signed_distance(x).min()) < CONTACT_SKINS * c.thickness
               for c in colliders)


def asked_loss(model: ClothModel, scene: Scene, h: float, substeps: int, ke_start: float,
               ke_end: float) -> float:
    """J: the kinetic energy the damping key took over a frame of `substeps` of h: per
    substep v ← k·v takes (1 − k²) of it, taken at the mean of the frame's start and end."""
    fabric = model.fabric
    k = (decay_factor(fabric.material.damping, h) if fabric is not None
         else damping_factor(scene.behavior.damping, h))
    if k == 1.0:
        return 0.0
    return substeps * (1.0 - k * k) * 0.5 * (ke_start + ke_end)


@dataclass
class DampingMeter:
    """The frames' numerical damping: the energy a frame starts from (the last one's end,
    so a frame's loss is measured from where the previous one left off), the last frame's
    value and the average reported."""
    start_energy: float | None = None  # J, the energy the next frame starts from
    frame: float | None = None         # 1/s, the last frame's; None: not measurable
    average: float | None = None       # 1/s, over about AVERAGE_FRAMES frames

    def forget(self) -> None:
        """A change no step made (a push, a pin, new values): no damping across it."""
        self.start_energy = None

    def begin(self, measurable_now: bool, energy_now) -> float | None:
        """The energy the frame about to run starts from (`energy_now()` if not known),
        None where it is not measurable."""
        if not measurable_now:
            self.start_energy = None
        elif self.start_energy is None:
            self.start_energy = energy_now()
        return self.start_energy

    def end(self, e_start: float, e_end: float, asked: float, free_at_start: float,
            dt: float) -> float:
        """The frame's numerical damping, 1/s; its end is the next frame's start."""
        self.start_energy = e_end
        self.frame = (e_start - e_end - asked) / (free_at_start * dt)
        return self.frame

    def unmeasured(self) -> None:
        """The frame could not be told apart (a contact, a tear, nothing bounds the sheet)."""
        self.start_energy = self.frame = None

    def report(self, halted: bool) -> None:
        """Fold the last frame into the average (None while not measurable)."""
        if self.frame is None or halted:
            self.average = None
        elif self.average is None:
            self.average = self.frame
        else:
            self.average += (self.frame - self.average) / AVERAGE_FRAMES
