"""Advancing whole frames: a synchronous `Simulation` (the step, the divergence guard, the
accuracy controller, statistics and immutable snapshots). sim_thread.py runs one in real time
on its own thread. What new settings rebuild is rebuild_policy.py's; the guard's tests of a
frame are guard.py's; the accuracy control's inputs are accuracy.py's; the user's gestures
are gestures.py's; statistics and snapshots are reporting.py's."""

from __future__ import annotations

import time
from typing import TYPE_CHECKING

import numpy as np

from .. import pipeline
from ..collision.held_contacts import check_held_particles, check_scene, held_inputs_differ
from ..effects.pins import with_user_pin
from ..model import build_model, nearest_pins, refitted
from ..params import same_structure
from ..state import ClothState
from . import gestures
from .accuracy import error_tolerance, measure_damping
from .guard import (GUARD_EASE_FRAMES, MAX_GUARD_LEVEL, SPRING_DIVERGED, energy_scale, finite,
                    frame_problem, halt_reason, load_measure, stretch_converged,
                    watches_energy)
from .measures import energy, free_energy, potential_floor
from .numerical_damping import DampingMeter, measurable
from .rebuild_policy import MODEL_KEYS, has_energy_source, needs_new_model, scene_material
from .reporting import Snapshot, measured_stats, snapshot_of
from .run_stats import FrameStats, RunStats
from .substep_control import ENERGY_MADE_TOLERANCE, SubstepController

if TYPE_CHECKING:
    from ...scene import Scene

# Read from here by tools and tests that name the runner's rules.
__all__ = ["MAX_GUARD_LEVEL", "MODEL_KEYS", "SPRING_DIVERGED", "Simulation", "Snapshot",
           "has_energy_source"]


class Simulation:
    """One cloth in one scene. Not thread-safe: `SimulationThread` serialises access."""

    def __init__(self, scene: Scene):
        self._rebuild(scene, model=True)

    # -- building -------------------------------------------------------------------------
    def _rebuild(self, scene: Scene, model: bool) -> None:
        """New settings. `model`: a new sheet, so a new run: every counter starts again.
        Otherwise the sheet goes on, but the recoveries and a halt were the old settings'."""
        b = scene.behavior
        new_model = build_model(scene.cloth, b, scene.pins, scene_material(scene)) if model \
            else self.model
        if model or held_inputs_differ(self.scene, scene):
            check_scene(scene, new_model)  # before any change: a refusal keeps all
        self.scene = scene
        if model:
            self.model = new_model
            self.state = ClothState.from_model(self.model)
            self._good = self.state.copy()  # the state before the current frame
            self._trial = self.state.copy()  # scratch for the stretch-convergence check
            self.frames = 0
            self.wall_s = 0.0
            self.last_step_s = 0.0
            self.penetration = 0.0
            self.substeps_run = 0  # every substep stepped, redone and trial frames included
        self.recoveries = 0
        self.halted: str | None = None  # why stepping stopped, if it did
        self.control = SubstepController(error_tolerance(scene, self.model), b.substeps,
                                         b.max_substeps, adaptive=b.adaptive,
                                         energy_tolerance=b.energy_tolerance or None)
        self.frame_error = 0.0  # solve error after the last frame (when it was measured)
        self._measured_met: bool | None = None  # fixed substeps: the last stats()' verdict
        self.damping_meter = DampingMeter()  # numerical damping of the frames
        self._guard_level = 0
        self._sources = has_energy_source(scene)
        self._find_nearest_pins()
        self._build_step()
        solver = self.step.solver
        if solver is not None and solver.bounds_energy_made:
            self.control.made_tolerance = ENERGY_MADE_TOLERANCE
        # A solver that leaves no solve error (springs stretch as their stiffness says,
        # whatever the step): the tolerance is reported, the substeps are the guard's alone.
        if solver is not None and self._solve_error() is None:
            self.control.adaptive = False

    def _build_step(self) -> None:
        self.step = pipeline.build(self.scene, self.model,
                                   self.control.substeps << self._guard_level)

    def _find_nearest_pins(self) -> None:
        """Each particle's nearest hard pin and flat-sheet distance to it: what bounds how
        low the sheet can hang (measures.potential_floor)."""
        m = self.model
        self._nearest_pin = self._pin_distance = None
        if len(m.pinned):
            near, dist, sample = nearest_pins(m.rest_positions, m.pinned, self.scene.behavior.seed)
            self._nearest_pin = near if sample is None else np.searchsorted(m.pinned, sample[near])
            self._pin_distance = dist

    def set_scene(self, scene: Scene) -> bool:
        """Apply new settings, rebuilding only what changed. Returns whether the sheet was
        rebuilt (and so restarted). A scene that holds a particle in an object is refused
        with SceneError, changing nothing (held_contacts.check_scene: not checked again
        where the app checked the same before it asked)."""
        if same_structure(scene, self.scene):
            self._retune(scene)
            return False
        rebuild_model = needs_new_model(scene, self.scene)
        self._rebuild(scene, model=rebuild_model)
        return rebuild_model

    def _retune(self, scene: Scene) -> None:
        """New values of the step's parameters alone (params.py): the sheet, the step (its
        sweep plan, its kernels' thread choice), the substep controller and the guard's
        level run on, and the next substep reads the values. A halt was the old values'
        verdict, so stepping resumes; if it diverges again, the guard halts it again."""
        if scene.cloth != self.scene.cloth or scene.material != self.scene.material:
            self.model = refitted(self.model, scene.cloth, scene_material(scene))
        self.scene = scene
        self.step.retune(scene, self.model)
        self.damping_meter.forget()  # the energy's terms did (gravity): no damping across it
        self.halted = None

    def reset(self) -> None:
        """Start the run again: a new sheet, and every counter and halt cleared."""
        self._rebuild(self.scene, model=True)

    # -- stepping -------------------------------------------------------------------------
    def advance_frame(self) -> None:
        """One frame. A diverging frame is undone and retried with more substeps (the guard);
        with `adaptive`, a frame that leaves more stretch than the tolerance is redone with
        more substeps (the controller)."""
        if self.halted:
            return
        t0 = time.perf_counter()
        if self._finite():  # (a state broken between frames falls back further)
            self._good.restore(self.state)  # the frame's start, with bumps since the last
        e0 = (energy_scale(self.model, self.state, self.scene, self.step)
              if watches_energy(self.step, self._sources) else None)
        e_start = self.damping_meter.begin(self._damping_measurable(), self._energy)
        self._run_frame()
        while not self.halted:
            problem = frame_problem(self.model, self.state, self.scene, self.step, e0)
            measure = load_measure(problem)
            if measure is not None and self._converges(measure):
                problem = None
            if problem:
                self._recover()
                continue
            redo = self._redo_for_accuracy(e_start)
            if redo is None:
                break
            self.state.restore(self._good)
            self._build_step()
            self._run_frame()
        # Measured by the step that ran the frame: a rebuilt step's moving colliders would
        # stand where they were at t = 0 until they first run.
        if self.step.colliders:
            self.penetration = max(self.penetration, self.step.penetration(self.state.x))
        if not self.halted:  # (not adaptive: it only records whether the frame met them)
            planned = self.control.substeps
            if self.control.accept(self.frame_error, self.damping_meter.frame) != planned:
                self._build_step()
        self.damping_meter.report(bool(self.halted))
        if self._guard_level and self.frames % GUARD_EASE_FRAMES == 0 and not self.halted:
            self._guard_level -= 1  # try fewer substeps again now and then
            self._build_step()
        self.last_step_s = time.perf_counter() - t0
        self.wall_s += self.last_step_s
        self.frames += 1

    def _run_frame(self) -> None:
        self.step.frame(self.state)
        if self.step.effects:
            self.substeps_run += self.step.substeps

    def _redo_for_accuracy(self, e_start: float | None) -> int | None:
        """Measure the frame's solve error and numerical damping and ask the controller."""
        measure_damping(self.damping_meter, e_start, self._energy, self.model, self._good,
                        self.state, self.scene, self.step, self._pin_distance,
                        self._nearest_pin)
        if not self.control.adaptive or not self.model.num_constraints:
            return None
        self.frame_error = self._solve_error() or 0.0  # (no solver: the sheet is frozen)
        return self.control.redo_with(self.frame_error)

    # -- numerical damping (numerical_damping.py) -----------------------------------------
    @property
    def numerical_damping(self) -> float | None:
        """Averaged over recent frames, 1/s; None while not measurable."""
        return self.damping_meter.average

    def _damping_measurable(self) -> bool:
        return measurable(self.scene, self.model, self.step.solver, bool(self.step.effects),
                          self._sources, self._pin_distance is not None)

    def free_energy(self) -> float | None:
        """The energy the sheet could still give up now, J (measures.free_energy), or None
        where nothing bounds how low it can go."""
        floor = potential_floor(self.model, self.state, self.scene, self._pin_distance,
                                self._nearest_pin)
        return None if floor is None else free_energy(self._energy(), floor, self.model)

    # -- the divergence guard (guard.py) --------------------------------------------------
    def _finite(self) -> bool:
        return finite(self.state)

    def _converges(self, measure) -> bool:
        """Run the frame again from its start at twice the substeps: the stretch (or spread,
        `measure`) the scene's loads impose stays (within guard.STRETCH_CONVERGED), an
        unstable step's collapses. The frame's own result is kept either way; the check's
        run is a trial."""
        s1 = measure(self.model, self.state)
        self._trial.restore(self.state)
        self.state.restore(self._good)
        self._guard_level += 1
        self._build_step()
        self._run_frame()
        s2 = measure(self.model, self.state) if self._finite() else float("inf")
        self._guard_level -= 1
        self._build_step()
        self.state.restore(self._trial)
        return stretch_converged(s1, s2)

    def _recover(self) -> None:
        self.recoveries += 1
        self.state.restore(self._good)
        if self._guard_level >= MAX_GUARD_LEVEL:
            # Even 16× the substeps diverges: hold the last good state and say why, rather
            # than show garbage or restart the sheet every frame.
            self.halted = halt_reason(self.step)
            return
        self._guard_level += 1
        self._build_step()
        self._run_frame()

    # -- gestures (gestures.py) -----------------------------------------------------------
    def bump(self, particle: int, displacement, radius: float = 1.5) -> None:
        """Push one particle, and its grid neighbours less (gestures.bump)."""
        gestures.bump(self.model, self.state, particle, displacement, radius,
                      self.scene.behavior.frame_rate)
        self.damping_meter.forget()  # the user's push is no numerical damping

    def pin(self, particle: int, position) -> None:
        """Hold `particle` exactly at `position` until the sheet is rebuilt (the app's pin
        gesture; a restart brings back the scene's pins alone). Raises SceneError, changing
        nothing, where a held particle may not be: in the floor or an object's skin, or on a
        particle a soft or moving group places."""
        gestures.check_pin_height(self.scene.scene, position)
        model, slot = with_user_pin(self.model, int(particle), position)
        check_held_particles(self.scene, model)
        gestures.hold(self.state, particle, slot, position)
        self.model = model
        self._good, self._trial = self.state.copy(), self.state.copy()
        self._find_nearest_pins()
        self.damping_meter.forget()  # the pin moved a particle: a jump no step made
        self._build_step()

    def cut(self, p0: int, p1: int) -> int:
        """Cut the sheet between two particles (gestures.cut); returns how many constraints
        were cut. A restart heals the sheet."""
        return gestures.cut(self.model, self.state, p0, p1)

    # -- reporting (reporting.py) ---------------------------------------------------------
    def _solve_error(self) -> float | None:
        """The frame's solve error, as the step's solver measures it (None: none to bound)."""
        solver = self.step.solver
        return None if solver is None else solver.solve_error(self.state)

    def _energy(self) -> float:
        return energy(self.model, self.state, self.scene, self.step.solver)

    def frame_stats(self) -> FrameStats:
        """The statistics cheap enough for every frame."""
        adaptive = self.control.adaptive
        return FrameStats(
            frames=self.frames, steps=self.state.steps, torn=self.state.torn, t=self.state.t,
            recoveries=self.recoveries, halted=self.halted,
            frame_ms=1e3 * self.last_step_s,
            mean_frame_ms=1e3 * self.wall_s / self.frames if self.frames else 0.0,
            step_ms=1e3 * self.last_step_s / self.step.substeps,
            substeps_used=self.step.substeps, wall_s=self.wall_s,
            numerical_damping=self.numerical_damping,
            tolerance_met=self.control.met if adaptive else self._measured_met,
            frame_error=self.frame_error if adaptive else None)

    def stats(self) -> RunStats:
        """Every statistic, the costly ones measured now."""
        is_finite = self._finite()
        error = self._solve_error() if is_finite else None
        energy_tolerance = self.control.energy_tolerance
        if not self.control.adaptive:  # (adaptive: the controller's verdict, per frame)
            self._measured_met = (None if error is None and energy_tolerance is None
                                  else self.control.meets(error or 0.0))
        return measured_stats(self.model, self.state, self.scene, self.step, is_finite, error,
                              self.control.tolerance, energy_tolerance, self._energy(),
                              self.penetration).refreshed(self.frame_stats())

    def snapshot(self, stats: RunStats | None = None) -> Snapshot:
        """A snapshot with full statistics, or with `stats` (an earlier full set, or
        `RunStats()` for none) refreshed by this frame's cheap ones."""
        stats = self.stats() if stats is None else stats.refreshed(self.frame_stats())
        return snapshot_of(self.model, self.state, self.scene, self.step, self.frames, stats)
