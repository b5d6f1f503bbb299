"""Advancing whole frames: a synchronous `Simulation`, and `SimulationThread` that runs one
at a fixed timestep in its own thread, applying queued commands between frames and
publishing immutable snapshots."""

from __future__ import annotations

import dataclasses
import threading
import time
from collections import deque
from dataclasses import dataclass
from typing import Callable

import numpy as np

from ..scene import Scene
from . import pipeline
from .model import ClothModel, build_model
from .state import ClothState

# What forces a rebuild of the model (topology, masses, pins) rather than only the step.
MODEL_KEYS = {("cloth", k) for k in ("size", "resolution", "pinned", "pin_fraction", "mass",
                                     "height")} | \
             {("behavior", k) for k in ("structural", "shear", "bending", "seed",
                                        "tethers", "wave")}
SPRING_DIVERGED = 1.0  # |L/L0 − 1| beyond which a springs integrator counts as diverged
MAX_GUARD_LEVEL = 4
MAX_CATCH_UP = 6  # frames (100 ms at 60 Hz) the thread may run back to back to keep time  # a diverging frame is retried with up to 2**4 = 16× the substeps


def stretch(model: ClothModel, x: np.ndarray) -> tuple[float, float]:
    """Max and mean of |L/L0 − 1| over the enabled constraints."""
    if not model.num_constraints:
        return 0.0, 0.0
    e = model.edges
    d = x[e[:, 0]] - x[e[:, 1]]
    r = np.abs(np.sqrt(np.einsum("ij,ij->i", d, d)) / model.rest_length - 1.0)
    return float(r.max()), float(r.mean())


def energy(model: ClothModel, state: ClothState, scene: Scene) -> float:
    """Kinetic + gravitational (height from y = 0) + elastic energy, J. Elastic: springs of
    stiffness k, xpbd constraints of compliance α (stiffness 1/α); pbd's rigid constraints
    store none."""
    m = model.mass
    e = 0.5 * float(np.dot(m, np.einsum("ij,ij->i", state.v, state.v)))
    if scene.forces.gravity:
        e += scene.forces.gravity_strength * float(np.dot(m, state.x[:, 1]))
    b = scene.behavior
    k = b.stiffness if b.solver == "springs" else \
        1.0 / b.compliance if b.solver == "xpbd" and b.compliance > 0 else 0.0
    if k and model.num_constraints:
        from .springs import spring_energy
        e += spring_energy(state.x, model.edges, model.rest_length, k)
    return e


@dataclass(frozen=True)
class Snapshot:
    """What the renderer and the UI get each frame: copies, never the live arrays."""
    positions: np.ndarray
    frame: int
    t: float
    stats: dict
    model: ClothModel
    scene: Scene
    objects: tuple = ()  # ObjectPose of every object, where it is at time t


class Simulation:
    """One cloth in one scene. Not thread-safe: `SimulationThread` serialises access."""

    def __init__(self, scene: Scene):
        self._rebuild(scene, model=True)

    # -- building -------------------------------------------------------------------------
    def _rebuild(self, scene: Scene, model: bool) -> None:
        self.scene = scene
        if model:
            self.model = build_model(scene.cloth, scene.behavior)
            self.state = ClothState.from_model(self.model)
            self._start_run()
            self._free = self.model.inv_mass > 0.0  # pins move as prescribed, however fast
        self.step = pipeline.build(scene, self.model)
        self._guard_level = 0
        self._good = self.state.copy()
        self.halted: str | None = None  # why stepping stopped, if it did

    def set_scene(self, scene: Scene) -> bool:
        """Apply new settings, rebuilding only what changed. Returns whether the sheet was
        rebuilt (and so restarted)."""
        changed = {(s, f.name) for s in ("cloth", "behavior")
                   for f in dataclasses.fields(getattr(scene, s))
                   if getattr(getattr(scene, s), f.name) != getattr(getattr(self.scene, s), f.name)}
        rebuild_model = bool(changed & MODEL_KEYS)
        self._rebuild(scene, model=rebuild_model)
        return rebuild_model

    def _start_run(self) -> None:
        """A new sheet at rest starts a new run: what was counted in the last one (frames,
        time, retried frames, deepest penetration) must not be shown as this one's."""
        self.frames = 0
        self.wall_s = 0.0
        self.last_step_s = 0.0
        self.recoveries = 0
        self.penetration = 0.0

    def reset(self) -> None:
        self._rebuild(self.scene, model=True)

    # -- stepping -------------------------------------------------------------------------
    def advance_frame(self) -> None:
        """One frame; a diverging frame is undone and retried with more substeps."""
        if self.halted:
            return
        t0 = time.perf_counter()
        self.step.frame(self.state)
        while not self._healthy() and not self.halted:
            self._recover()
        if self._guard_level and self.frames % 60 == 0:
            self._guard_level -= 1  # try the scene's own substeps again now and then
            self.step = pipeline.build(self.scene, self.model,
                                       self.scene.behavior.substeps << self._guard_level)
        self.last_step_s = time.perf_counter() - t0
        self.wall_s += self.last_step_s
        self.frames += 1
        self._good.restore(self.state)
        if self.step.colliders:
            self.penetration = max(self.penetration, self.step.penetration(self.state.x))

    def _healthy(self) -> bool:
        """Finite, no runaway speed, and (springs only) no spring at over twice its rest
        length. Position-based solvers keep speeds clamped and may legitimately stretch a lot
        at few iterations; a force-based integrator going unstable shows first as stretch,
        since its speeds are clamped too."""
        if not self.state.is_finite():
            return False
        b = self.scene.behavior
        if float(np.max(np.abs(self.state.v[self._free]), initial=0.0)) > 4.0 * b.max_speed:
            return False
        return b.solver != "springs" or stretch(self.model, self.state.x)[0] <= SPRING_DIVERGED

    def _recover(self) -> None:
        self.recoveries += 1
        self.state.restore(self._good)
        if self._guard_level >= MAX_GUARD_LEVEL:
            # Even 16× the substeps diverges: hold the last good state and say why, rather
            # than show garbage or restart the sheet every frame.
            b = self.scene.behavior
            self.halted = (f"the step diverges even at {b.substeps << MAX_GUARD_LEVEL} substeps "
                           f"per frame; lower behavior.stiffness, raise behavior.substeps"
                           + (" or use behavior.integrator = implicit_euler"
                              if b.solver == "springs" else "")
                           + ", then restart")
            return
        self._guard_level += 1
        self.step = pipeline.build(self.scene, self.model,
                                   self.scene.behavior.substeps << self._guard_level)
        self.step.frame(self.state)

    def bump(self, particle: int, displacement, radius: float = 1.5) -> None:
        """Push one particle, and its grid neighbours less (Gaussian falloff of `radius`
        spacings), giving them the velocity of moving that far in one frame."""
        m, n = self.model, self.model.n
        d = np.asarray(displacement, dtype=np.float64)
        i0, j0 = divmod(int(particle), n)
        r = int(np.ceil(2 * radius))
        ii, jj = np.meshgrid(np.arange(max(0, i0 - r), min(n, i0 + r + 1)),
                             np.arange(max(0, j0 - r), min(n, j0 + r + 1)), indexing="ij")
        idx = (ii * n + jj).ravel()
        w = np.exp(-((ii - i0) ** 2 + (jj - j0) ** 2).ravel() / (radius * radius))
        w[m.inv_mass[idx] == 0.0] = 0.0
        self.state.x[idx] += w[:, None] * d
        self.state.v[idx] += w[:, None] * d * self.scene.behavior.frame_rate

    # -- reporting ------------------------------------------------------------------------
    def stats(self) -> dict:
        x = self.state.x
        finite = self.state.is_finite()
        max_s, mean_s = stretch(self.model, x) if finite else (float("nan"),) * 2
        speed = np.sqrt(np.einsum("ij,ij->i", self.state.v, self.state.v))
        return {
            "particles": self.model.num_particles,
            "constraints": self.model.num_constraints,
            "frames": self.frames,
            "steps": self.state.steps,
            "t": self.state.t,
            "finite": finite,
            "min_y": float(x[:, 1].min()),
            "max_speed": float(speed.max()),
            "max_stretch": max_s,
            "mean_stretch": mean_s,
            "energy": energy(self.model, self.state, self.scene),
            "penetration": self.penetration,
            "effects": self.step.names,
            "recoveries": self.recoveries,
            "halted": self.halted,
            "frame_ms": 1e3 * self.last_step_s,            # simulation time of the last frame
            "step_ms": 1e3 * self.last_step_s / self.step.substeps,  # of one substep in it
            "substeps_used": self.step.substeps,            # more than asked while recovering
            "wall_s": self.wall_s,
        }

    def snapshot(self) -> Snapshot:
        poses = tuple(c.pose(self.state.t) for c in self.step.colliders if hasattr(c, "pose"))
        return Snapshot(self.state.x.copy(), self.frames, self.state.t, self.stats(),
                        self.model, self.scene, poses)


class SimulationThread:
    """Runs a Simulation in real time (one frame per 1/frame_rate wall seconds, or as fast as
    it can) on a daemon thread. Other threads talk to it only through `submit` and read
    `latest`; `on_snapshot` is called from the simulation thread after every frame."""

    def __init__(self, scene: Scene, on_snapshot: Callable[[Snapshot], None] | None = None):
        self.sim = Simulation(scene)
        self.on_snapshot = on_snapshot
        self.paused = False
        self._commands: deque[Callable[[Simulation], None]] = deque()
        self._stop = threading.Event()
        self._wake = threading.Event()
        self._lock = threading.Lock()
        self._latest = self.sim.snapshot()
        self._thread = threading.Thread(target=self._run, name="cloth-sim", daemon=True)
        self.error: BaseException | None = None

    def start(self) -> "SimulationThread":
        self._thread.start()
        return self

    def stop(self, timeout: float = 1.0) -> None:
        self._stop.set()
        self._wake.set()
        self._thread.join(timeout)

    def pause(self, paused: bool) -> None:
        """Pause or resume; the thread publishes a snapshot at once either way."""
        self.paused = paused
        self.submit(lambda sim: None)

    def submit(self, command: Callable[[Simulation], None]) -> None:
        """Run `command(sim)` on the simulation thread between frames."""
        self._commands.append(command)
        self._wake.set()

    @property
    def latest(self) -> Snapshot:
        with self._lock:
            return self._latest

    def _publish(self) -> None:
        snap = self.sim.snapshot()
        with self._lock:
            self._latest = snap
        if self.on_snapshot is not None:
            self.on_snapshot(snap)

    def _run(self) -> None:
        """Frames are due every 1/frame_rate s of wall time. A late thread (the GIL held by the
        renderer or the UI, a slow frame) catches up with up to MAX_CATCH_UP frames at once,
        so the simulation keeps real time; further behind than that, it drops the backlog
        rather than run ever faster."""
        next_t = time.perf_counter()  # when the next frame is due
        try:
            while not self._stop.is_set():
                changed = False
                while self._commands:
                    self._commands.popleft()(self.sim)
                    changed = True
                now = time.perf_counter()
                if self.paused:
                    next_t = now
                else:
                    period = 1.0 / self.sim.scene.behavior.frame_rate
                    for _ in range(MAX_CATCH_UP):
                        if now < next_t:
                            break
                        self.sim.advance_frame()
                        next_t += period
                        changed = True
                    if now >= next_t:
                        next_t = now + period
                if changed:
                    self._publish()
                wait = next_t - time.perf_counter() if not self.paused else 0.25
                if wait > 0:
                    self._wake.wait(wait)
                    self._wake.clear()
        except BaseException as e:  # reported to the UI, never lost silently
            self.error = e
            if self.on_snapshot is not None:
                self.on_snapshot(None)
