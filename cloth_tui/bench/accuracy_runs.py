"""The work-precision study's test scene (documented in docs/accuracy.md and accuracy.py) and
one run of it: substep by substep through `pipeline.build(...).substep`, not through the
runner, whose recovery would retry a diverging frame with more substeps and so hide
instability. A run that produces NaN/inf, stretches an edge past `BLOWUP_STRETCH` or moves
a particle further than `BLOWUP_DISTANCE` from its start is stopped and marked
stable = False; a run never raises on an unstable step."""

from __future__ import annotations

import dataclasses
import math
import time
from dataclasses import dataclass, field

import numpy as np

from ..scene import Scene
from ..sim import pipeline
from ..sim.model import build_model
from ..sim.run.measures import energy, stretch
from ..sim.state import ClothState

BLOWUP_STRETCH = 1.0                  # |L/L0 − 1| beyond which a run counts as blown up
BLOWUP_DISTANCE = 10.0                # × sheet size: a particle this far from its start
CHECK_INTERVAL = 0.01                 # s of simulated time between blow-up checks
MAX_RATE = 10000.0                    # scene.behavior.frame_rate upper bound


@dataclass
class StudyConfig:
    """Everything that defines the study; `quick()` and `full()` are the two shipped sizes."""
    n: int = 8
    size: float = 0.5                 # m
    mass: float = 0.2                 # kg, whole sheet
    gravity: float = 9.81             # m/s²
    stiffness: float = 50.0           # N/m, springs (xpbd uses compliance = 1/stiffness)
    t_end: float = 0.5                # s
    ref_dt: float = 1.0 / 32000       # s, RK4 reference
    # timesteps per springs integrator (s); each ladder is in its asymptotic range
    ladders: dict = field(default_factory=dict)
    pbd_dts: tuple = ()               # timesteps for pbd and xpbd
    pbd_iterations: tuple = (4, 16)
    stability_stiffness: tuple = ()   # N/m, the three stiffnesses of the stability map
    stability_t_end: float = 0.5      # s, horizon of a stability run
    stability_range: tuple = (1e-5, 0.02)  # s, bisection bracket of dt
    stability_bisections: int = 7
    sag_iterations: tuple = (1, 4, 16, 64)
    sag_compliance: float = 0.005     # m/N for xpbd in the sag study
    sag_t_end: float = 3.0            # s, settling time of the sag study
    sag_damping: float = 0.1          # behavior.damping while settling
    sag_substeps: int = 4             # per 1/60 s frame
    timing_budget: float = 0.1        # s: a point is re-timed while its runs took less
    cantilever_links: tuple = (5, 10)  # the physical reference's resolutions (accuracy_physical)

    @classmethod
    def full(cls) -> "StudyConfig":
        n = lambda *ks: tuple(1.0 / k for k in ks)  # noqa: E731
        return cls(
            ladders={
                "explicit_euler": n(2000, 4000, 8000, 16000),
                "symplectic_euler": n(250, 500, 1000, 2000, 4000),
                "verlet": n(250, 500, 1000, 2000, 4000),
                "midpoint": n(500, 1000, 2000, 4000, 8000),
                "rk4": n(125, 250, 500, 1000, 2000),
                "implicit_euler": n(1000, 2000, 4000, 8000, 16000),
            },
            pbd_dts=n(60, 120, 240, 480, 960),
            pbd_iterations=(1, 4, 16, 64),
            stability_stiffness=(20.0, 200.0, 2000.0),
            stability_bisections=9,
            cantilever_links=(5, 10, 20, 40),
        )

    @classmethod
    def quick(cls) -> "StudyConfig":
        n = lambda *ks: tuple(1.0 / k for k in ks)  # noqa: E731
        return cls(
            ref_dt=1.0 / 16000,
            ladders={
                "explicit_euler": n(2000, 4000, 8000),
                "symplectic_euler": n(500, 1000, 2000),
                "verlet": n(250, 500, 1000),
                "midpoint": n(1000, 2000, 4000),
                "rk4": n(125, 250, 500),
                "implicit_euler": n(2000, 4000, 8000),
            },
            pbd_dts=n(60, 240, 960),
            pbd_iterations=(4, 16),
            stability_stiffness=(20.0, 200.0, 2000.0),
            stability_bisections=6,
            stability_t_end=0.3,
            sag_t_end=2.0,
            timing_budget=0.05,
        )


# --- the scene -------------------------------------------------------------------------------

def study_scene(cfg: StudyConfig, solver: str = "springs", integrator: str = "rk4",
                dt: float = 1e-3, iterations: int = 4, stiffness: float | None = None,
                compliance: float | None = None, damping: float = 0.0,
                pinned: str = "two_corners") -> Scene:
    """The test scene with substep `dt` (frame_rate·substeps = 1/dt)."""
    k = cfg.stiffness if stiffness is None else stiffness
    substeps = max(1, math.ceil(1.0 / (dt * MAX_RATE)))
    s = Scene(name="accuracy")
    c, f, sc, b = s.cloth, s.forces, s.scene, s.behavior
    c.resolution, c.size, c.mass, c.height = cfg.n, cfg.size, cfg.mass, 0.0
    c.pinned = "corners" if pinned == "corners" else "one_edge"  # two corners: see study_model
    f.gravity, f.gravity_strength = True, cfg.gravity
    sc.floor = False
    b.solver = solver
    b.integrator = integrator if solver == "springs" else "verlet"
    b.stiffness = k
    b.spring_damping = 0.0
    b.compliance = 1.0 / k if compliance is None else compliance
    b.damping = damping
    b.tethers = False  # the study measures the solvers alone
    b.iterations = iterations
    b.substeps = substeps
    b.frame_rate = 1.0 / (dt * substeps)
    b.max_speed = 1e5
    return s


def study_model(scene: Scene, pinned: str = "two_corners"):
    """The scene's model; `two_corners` pins only particles (0, 0) and (0, nx−1), the ends
    of row 0."""
    model = build_model(scene.cloth, scene.behavior)
    if pinned != "two_corners":
        return model
    pins = np.array([0, model.nx - 1], dtype=np.int64)
    inv_mass = 1.0 / model.mass
    inv_mass[pins] = 0.0
    for a in (pins, inv_mass):
        a.setflags(write=False)
    # (study_scene turns tethers off, so none refer to the pins replaced here)
    return dataclasses.replace(model, pinned=pins, inv_mass=inv_mass)


@dataclass
class Run:
    x: np.ndarray | None      # final positions (None when unstable)
    stable: bool
    wall: float               # s of wall time the substeps cost (lower quartile of chunk rates)
    stretch: float            # max |L/L0 − 1| seen at the checks
    energy_drift: float       # (E(t_end) − E(0)) / (M g size)
    steps: int
    cpu: float = 0.0          # s of this thread's CPU time for the whole run (with checks)


def simulate(scene: Scene, model, t_end: float) -> Run:
    """Advance the scene to t_end substep by substep, with blow-up checks and no recovery."""
    step = pipeline.build(scene, model)
    state = ClothState.from_model(model)
    h = step.h
    steps = max(1, int(round(t_end / h)))
    check = max(1, int(round(CHECK_INTERVAL / h)))
    e0 = energy(model, state, scene, step.solver)
    scale = model.mass.sum() * max(scene.forces.gravity_strength, 1e-12) * model.extent
    x0 = state.x.copy()
    limit = BLOWUP_DISTANCE * model.extent
    worst, stable = 0.0, True
    rates = []  # wall time per substep of each chunk between checks
    done = 0
    cpu0 = time.thread_time()
    with np.errstate(all="ignore"):
        while done < steps:
            chunk = min(check, steps - done)
            t0 = time.perf_counter()
            for _ in range(chunk):
                step.substep(state)
            rates.append((time.perf_counter() - t0) / chunk)
            done += chunk
            x = state.x
            if not state.is_finite():
                stable = False
                break
            s = stretch(model, x)[0]
            worst = max(worst, s)
            if s > BLOWUP_STRETCH or float(np.max(np.abs(x - x0))) > limit:
                stable = False
                break
    cpu = time.thread_time() - cpu0
    drift = (energy(model, state, scene, step.solver) - e0) / scale if stable else math.nan
    # Other processes share the cores and preempt some chunks: the cost of a substep is the
    # lower quartile of the chunks' rates, which such interruptions do not reach.
    wall = float(np.percentile(rates, 25)) * steps if rates else 0.0
    return Run(state.x.copy() if stable else None, stable, wall, worst if stable else math.inf,
               drift, done, cpu)


def errors(x, x_ref) -> tuple[float, float]:
    """RMS and max over particles of |x − x_ref|, m."""
    d = np.sqrt(np.einsum("ij,ij->i", x - x_ref, x - x_ref))
    return float(np.sqrt(np.mean(d * d))), float(d.max())
