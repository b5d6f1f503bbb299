"""Advancing whole frames: a synchronous `Simulation` (the step, the divergence guard, the
accuracy controller, statistics and immutable snapshots). sim_thread.py runs one in real time
on its own thread."""

from __future__ import annotations

import dataclasses
import math
import time
from dataclasses import dataclass
from typing import TYPE_CHECKING

import numpy as np

from ...scene_keys import SceneError
from .. import pipeline
from .measures import (all_finite, energy, free_energy, gravitational_energy, kinetic_energy,
                       per_constraint, potential_floor, solve_error, stretch)
from ..collision.held_contacts import check_held_particles, held_inputs_differ
from ..model import ClothModel, build_model, nearest_pins, refitted, uses_tethers
from .numerical_damping import DampingMeter, asked_loss, measurable, touching
from ..params import same_structure
from ..effects.pins import with_user_pin
from .run_stats import FrameStats, RunStats
from ..state import ClothState
from .substep_control import SubstepController
from ..solvers import registry
from ..effects.tearing import cut_between, strength_tolerance, tear_strength

if TYPE_CHECKING:
    from ...scene import Scene

# What forces a rebuild of the model (topology, masses, pins) rather than only the step.
MODEL_KEYS = {("cloth", k) for k in ("size", "resolution", "pinned", "pin_fraction", "mass",
                                     "mass_model", "height")} | \
             {("behavior", k) for k in ("structural", "shear", "bending", "seed",
                                        "tethers", "wave")}
SPRING_DIVERGED = 1.0  # |L/L0 − 1| beyond which a springs integrator counts as diverged
# ... unless the same frame at twice the substeps ends this close to the same stretch: an
# unstable step's stretch collapses when h halves, a load's (a heavy sheet, pins, a wave, a
# moving object) stays.
STRETCH_CONVERGED = 0.1
# A force-based integrator going unstable pumps energy in. In a scene with no energy source
# (wind, fields, rain, a wave, moving objects or pins) a frame may not gain more than this
# share of the sheet's energy scale (M·g·size + its kinetic and elastic energy): damping,
# contacts and a stable integrator only lose energy, an unstable one gains it exponentially.
ENERGY_GAIN_DIVERGED = 0.05
# deeper in a skin than this (share of it, m of rounding), a contact will push: _energy_scale
OVERLAP_SHARE, OVERLAP_SLACK = 1e-3, 1e-9
MAX_GUARD_LEVEL = 4  # a diverging frame is retried with up to 2**4 = 16× the substeps
GUARD_EASE_FRAMES = 60  # frames between tries of half the substeps while recovering


def _material(scene: Scene):
    """The scene's material (materials.schema.Material), None for the original's keys."""
    return None if scene.material is None else scene.material.material


def has_energy_source(scene: Scene) -> bool:
    """Whether anything in the scene may add energy to the sheet (besides the user)."""
    f = scene.forces
    return (f.wind or f.custom != "none" or f.rain or scene.behavior.wave
            or (scene.scene.moving and scene.scene.object != "none")
            or any(o.motion != "static" for o in scene.objects)
            or any(g.keys for g in scene.pins))  # moving pin groups


@dataclass(frozen=True)
class Snapshot:
    """What the renderer and the UI get each frame: copies, never the live arrays. `stats`
    are complete only every STATS_INTERVAL s (see Simulation.snapshot)."""
    positions: np.ndarray
    frame: int
    t: float
    stats: RunStats
    model: ClothModel
    scene: Scene
    objects: tuple = ()  # ObjectPose of every object, where it is at time t
    alive: np.ndarray | None = None  # which constraints are intact; None: all (nothing torn)


class Simulation:
    """One cloth in one scene. Not thread-safe: `SimulationThread` serialises access."""

    def __init__(self, scene: Scene):
        self._rebuild(scene, model=True)

    # -- building -------------------------------------------------------------------------
    def _rebuild(self, scene: Scene, model: bool, held_checked: bool = False) -> None:
        """New settings. `model`: a new sheet, so a new run: every counter starts again.
        Otherwise the sheet goes on, but the recoveries and a halt were the old settings'.
        `held_checked`: the caller has run held_contacts.check_start on `scene`."""
        b = scene.behavior
        new_model = build_model(scene.cloth, b, scene.pins, _material(scene)) if model \
            else self.model
        if not held_checked and (model or held_inputs_differ(self.scene, scene)):
            check_held_particles(scene, new_model)  # before any change: a refusal keeps all
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
        # Springs stretch as their stiffness says, whatever the step: there the tolerance is
        # reported, and substeps are the guard's business alone.
        self.control = SubstepController(self._error_tolerance(), b.substeps, b.max_substeps,
                                         adaptive=b.adaptive and self._solves_constraints(),
                                         energy_tolerance=b.energy_tolerance or None)
        self.frame_error = 0.0  # solve error after the last frame (when it was measured)
        self._measured_met: bool | None = None  # fixed substeps: the last stats()' verdict
        self.damping_meter = DampingMeter()  # numerical damping of the frames
        self._guard_level = 0
        self._sources = has_energy_source(scene)
        self._find_nearest_pins()
        self._build_step()

    def _solves_constraints(self) -> bool:
        """Whether the scene's solver leaves a solve error to bound (registry.SolverSpec)."""
        return registry.spec(self.scene.behavior.solver).solves_constraints

    def _error_tolerance(self) -> float:
        """behavior.error_tolerance, or tighter where the sheet tears by strength: tight
        enough to know the tension to a tenth of the strength (tearing.strength_tolerance)."""
        tol = self.scene.behavior.error_tolerance
        strength = tear_strength(self.scene.behavior, self.model)
        return tol if strength is None else min(tol, strength_tolerance(self.model, strength))

    def _build_step(self) -> None:
        self.step = pipeline.build(self.scene, self.model,
                                   self.control.substeps << self._guard_level)
        self._alpha_tilde = None  # per constraint, for the step just built (when asked)

    def _find_nearest_pins(self) -> None:
        """Each particle's nearest hard pin and flat-sheet distance to it: what bounds how
        low the sheet can hang (measures.potential_floor)."""
        m = self.model
        self._nearest_pin = self._pin_distance = None
        if len(m.pinned):
            near, dist, sample = nearest_pins(m.rest_positions, m.pinned, self.scene.behavior.seed)
            self._nearest_pin = near if sample is None else np.searchsorted(m.pinned, sample[near])
            self._pin_distance = dist

    def set_scene(self, scene: Scene, held_checked: bool = False) -> bool:
        """Apply new settings, rebuilding only what changed. Returns whether the sheet was
        rebuilt (and so restarted). `held_checked`: the caller has checked `scene` for held
        particles in objects (held_contacts.check_start, as the app does before it asks),
        so it is not checked again here; otherwise a refusal raises SceneError, changing
        nothing."""
        if same_structure(scene, self.scene):
            self._retune(scene)
            return False
        changed = {(s, f.name) for s in ("cloth", "behavior")
                   for f in dataclasses.fields(getattr(scene, s))
                   if getattr(getattr(scene, s), f.name) != getattr(getattr(self.scene, s), f.name)}
        rebuild_model = bool(changed & MODEL_KEYS) or scene.pins != self.scene.pins \
            or scene.material != self.scene.material \
            or uses_tethers(scene.behavior, _material(scene)) \
            != uses_tethers(self.scene.behavior, _material(self.scene))
        self._rebuild(scene, model=rebuild_model, held_checked=held_checked)
        return rebuild_model

    def _retune(self, scene: Scene) -> None:
        """New values of the step's parameters alone (params.py): the sheet, the step (its
        sweep plan, its kernels' thread choice), the substep controller and the guard's
        level run on, and the next substep reads the values. A halt was the old values'
        verdict, so stepping resumes; if it diverges again, the guard halts it again."""
        if scene.cloth != self.scene.cloth or scene.material != self.scene.material:
            self.model = refitted(self.model, scene.cloth, _material(scene))
        self.scene = scene
        self.step.retune(scene, self.model)
        self._alpha_tilde = None  # α̃ may have changed
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
        e0 = self._energy_scale() if self._watch_energy() else None
        e_start = self.damping_meter.begin(self._damping_measurable(), self._energy)
        self._run_frame()
        while not self.halted:
            problem = self._problem(e0)
            if problem == "overstretched" and self._stretch_converges():
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
        self._measure_damping(e_start)
        if not self.control.adaptive or not self.model.num_constraints:
            return None
        self.frame_error = self._solve_error()
        return self.control.redo_with(self.frame_error)

    # -- numerical damping (numerical_damping.py) -----------------------------------------
    @property
    def numerical_damping(self) -> float | None:
        """Averaged over recent frames, 1/s; None while not measurable."""
        return self.damping_meter.average

    def _damping_measurable(self) -> bool:
        return measurable(self.scene, self.model, self.step.solver, bool(self.step.effects),
                          self._sources, self._pin_distance is not None)

    def _measure_damping(self, e_start: float | None) -> None:
        """The numerical damping of the frame just run, where it can be told apart."""
        if e_start is None or self.state.torn != self._good.torn \
                or touching(self.step.colliders, self.state.x):
            self.damping_meter.unmeasured()
            return
        floor = potential_floor(self.model, self._good, self.scene, self._pin_distance,
                                self._nearest_pin)
        if floor is None:
            self.damping_meter.unmeasured()
            return
        m = self.model
        asked = asked_loss(m, self.scene, self.step.h, self.step.substeps,
                           kinetic_energy(m, self._good), kinetic_energy(m, self.state))
        self.damping_meter.end(e_start, self._energy(), asked,
                               free_energy(e_start, floor, m),
                               1.0 / self.scene.behavior.frame_rate)

    def free_energy(self) -> float | None:
        """The energy the sheet could still give up now, J (measures.free_energy), or None
        where nothing bounds how low it can go."""
        floor = potential_floor(self.model, self.state, self.scene, self._pin_distance,
                                self._nearest_pin)
        return None if floor is None else free_energy(self._energy(), floor, self.model)

    def _watch_energy(self) -> bool:
        solver = self.step.solver
        return solver is not None and solver.watches_energy and not self._sources

    def _energy_scale(self) -> tuple[float, float]:
        """(energy, scale) at the start of a frame, for the energy-gain check; no bound
        (inf) where a contact will push a particle out of a skin at depth/h, a gain that
        more substeps raise: growth from a source, not from the step."""
        m, st, sc = self.model, self.state, self.scene
        internal = kinetic_energy(m, st) + self.step.solver.elastic_energy(st)
        g = sc.forces.gravity_strength if sc.forces.gravity else 0.0
        scale = float(m.mass.sum()) * g * m.extent + internal + 1e-12
        if self._overlapping():
            scale = math.inf
        return internal + gravitational_energy(m, st, sc), scale

    def _overlapping(self) -> bool:
        """A free particle deeper in a skin than contacts leave one (placed or bumped there)."""
        free = self.model.inv_mass != 0.0
        return any(c.signed_distance(self.state.x)[free].min(initial=math.inf)
                   < c.thickness * (1.0 - OVERLAP_SHARE) - OVERLAP_SLACK
                   for c in self.step.colliders)

    def _finite(self) -> bool:
        return all_finite(self.state.x, self.state.v)

    def _problem(self, e0: tuple[float, float] | None) -> str | None:
        """What is wrong with the frame just run, or None: not finite, or (a force-based
        solver, whose `watches_energy`) energy gained from nowhere or, for explicit
        integrators, a spring at over twice its rest length. Every solver clamps speeds to
        max_speed, so speed shows nothing. A position-based step cannot run away while
        finite (its prediction is clamped, projection and contacts only move particles
        towards satisfied constraints and surfaces), and may legitimately stretch a lot at
        few iterations; a force-based integrator going unstable shows as energy or as
        stretch."""
        if not self._finite():
            return "not finite"
        solver = self.step.solver
        if solver is None or not solver.watches_energy:
            return None
        if e0 is not None:
            e_start, scale = e0
            if self._energy() - e_start > ENERGY_GAIN_DIVERGED * scale:
                return "energy gained"
        if solver.may_overstretch_unstably and self._max_stretch() > SPRING_DIVERGED:
            return "overstretched"
        return None

    def _max_stretch(self) -> float:
        return stretch(self.model, self.state.x, self.state.alive)[0]

    def _stretch_converges(self) -> bool:
        """Run the frame again from its start at twice the substeps: the stretch the scene's
        loads impose stays (within STRETCH_CONVERGED), an unstable step's collapses. The
        frame's own result is kept either way; the check's run is a trial."""
        s1 = self._max_stretch()
        self._trial.restore(self.state)
        self.state.restore(self._good)
        self._guard_level += 1
        self._build_step()
        self._run_frame()
        s2 = self._max_stretch() if self._finite() else math.inf
        self._guard_level -= 1
        self._build_step()
        self.state.restore(self._trial)
        return abs(s2 - s1) <= STRETCH_CONVERGED * s1

    def _recover(self) -> None:
        self.recoveries += 1
        self.state.restore(self._good)
        if self._guard_level >= MAX_GUARD_LEVEL:
            # Even 16× the substeps diverges: hold the last good state and say why, rather
            # than show garbage or restart the sheet every frame.
            self.halted = (f"the step diverges even at {self.step.substeps} substeps per "
                           f"frame; {self.step.solver.halt_advice()}, then restart")
            return
        self._guard_level += 1
        self._build_step()
        self._run_frame()

    def bump(self, particle: int, displacement, radius: float = 1.5) -> None:
        """Push one particle, and its grid neighbours less (Gaussian falloff of `radius`
        spacings), giving them the velocity of moving that far in one frame."""
        m = self.model
        d = np.asarray(displacement, dtype=np.float64)
        i0, j0 = divmod(int(particle), m.nx)
        r = int(np.ceil(2 * radius))
        ii, jj = np.meshgrid(np.arange(max(0, i0 - r), min(m.nz, i0 + r + 1)),
                             np.arange(max(0, j0 - r), min(m.nx, j0 + r + 1)), indexing="ij")
        idx = (ii * m.nx + jj).ravel()
        w = np.exp(-((ii - i0) ** 2 + (jj - j0) ** 2).ravel() / (radius * radius))
        w[m.inv_mass[idx] == 0.0] = 0.0
        self.state.x[idx] += w[:, None] * d
        self.state.v[idx] += w[:, None] * d * self.scene.behavior.frame_rate
        self.damping_meter.forget()  # the user's push is no numerical damping

    def pin(self, particle: int, position) -> None:
        """Hold `particle` exactly at `position` until the sheet is rebuilt (the app's pin
        gesture; a restart brings back the scene's pins alone). Raises SceneError, changing
        nothing, where a held particle may not be: in the floor or an object's skin, or on a
        particle a soft or moving group places."""
        s = self.scene.scene
        if s.floor and float(position[1]) < s.floor_height + s.thickness:
            raise SceneError(f"a pin at height {float(position[1]):.3g} m would hold the "
                             f"particle inside the floor (scene.floor_height = "
                             f"{s.floor_height:g} m + scene.thickness = {s.thickness:g} m)")
        model, slot = with_user_pin(self.model, int(particle), position)
        check_held_particles(self.scene, model)
        st = self.state
        p = np.asarray(position, np.float64)
        if slot == len(st.anchors):
            st.anchors = np.vstack([st.anchors, p])
        st.anchors[slot] = p
        st.x[particle] = st.x_prev[particle] = p
        st.v[particle] = 0.0
        self.model = model
        self._good, self._trial = st.copy(), st.copy()
        self._find_nearest_pins()
        self.damping_meter.forget()  # the pin moved a particle: a jump no step made
        self._build_step()

    def cut(self, p0: int, p1: int) -> int:
        """Cut the sheet between two particles (tearing.cut_between); returns how many
        constraints were cut. A restart heals the sheet."""
        n = self.model.num_particles
        if not (0 <= int(p0) < n and 0 <= int(p1) < n):
            return 0
        return cut_between(self.model, self.state, int(p0), int(p1))

    # -- reporting ------------------------------------------------------------------------
    def _alpha_tilde_now(self) -> np.ndarray:
        """α̃ = α/h² of the step's constraints, one per constraint (0 for rigid ones and
        springs), made again only when the solver's is another (a measured fabric's edges
        take a new α each substep: sim/stretch_curve.py)."""
        solver = self.step.solver
        source = 0.0 if solver is None else solver.alpha_tilde
        if self._alpha_tilde is None or source is not self._alpha_tilde_of:
            self._alpha_tilde = per_constraint(source, self.model.num_constraints)
            self._alpha_tilde_of = source
        return self._alpha_tilde

    def _solve_error(self) -> float:
        solver = self.step.solver  # pbd keeps a λ array too (zeros), so nothing is allocated
        lambdas = None if solver is None else solver.lambdas
        return solve_error(self.model, self.state.x, self.state.alive, lambdas,
                           self._alpha_tilde_now())

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
        x = self.state.x
        finite = self._finite()
        max_s, mean_s = (stretch(self.model, x, self.state.alive) if finite
                         else (float("nan"),) * 2)
        speed = np.sqrt(np.einsum("ij,ij->i", self.state.v, self.state.v))
        error = self._solve_error() if finite and self._solves_constraints() else None
        energy_tolerance = self.control.energy_tolerance
        if not self.control.adaptive:  # (adaptive: the controller's verdict, per frame)
            self._measured_met = (None if error is None and energy_tolerance is None
                                  else self.control.meets(error or 0.0))
        return RunStats(
            measured=True,
            particles=self.model.num_particles, constraints=self.model.num_constraints,
            finite=finite, min_y=float(x[:, 1].min()), max_speed=float(speed.max()),
            max_stretch=max_s, mean_stretch=mean_s, solver=self.scene.behavior.solver,
            error=error,
            # springs have no constraint solve to be off its equilibrium: nothing to bound
            error_tolerance=None if error is None else self.control.tolerance,
            energy_tolerance=energy_tolerance, energy=self._energy(),
            penetration=self.penetration, effects=tuple(self.step.names),
            material=None if self.scene.material is None else self.scene.material.name,
        ).refreshed(self.frame_stats())

    def snapshot(self, stats: RunStats | None = None) -> Snapshot:
        """A snapshot with full statistics, or with `stats` (an earlier full set, or
        `RunStats()` for none) refreshed by this frame's cheap ones."""
        stats = self.stats() if stats is None else stats.refreshed(self.frame_stats())
        poses = tuple(p for p in (c.pose(self.state.t) for c in self.step.colliders) if p)
        alive = self.state.alive.copy() if self.state.torn else None
        return Snapshot(self.state.x.copy(), self.frames, self.state.t, stats,
                        self.model, self.scene, poses, alive)
