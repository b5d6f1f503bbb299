"""The lab's tests of a strip without bending stiffness: `catenary` (a strip hung between
two hooks closer than its length, its sag against y = a cosh(x/a)) and `swing` (a strip
hanging from its top edge, its period against the hanging chain's ω₁ = (j₀,₁/2)√(g/L)).
Both need only mass and inextensibility: the strip's distance constraints (pbd, bending
off), solved to a residual stretch below the discretisation's error."""

from __future__ import annotations

import math

import numpy as np

from .catenary import catenary, chain_sag
from .chain import bessel_j0, bessel_j0_zero, hanging_chain_period, lumped_chain_omega
from .strips import particles_across, strip_scene, timed_frames, warmed_simulation
from .study import Case, Experiment, Measurement

LENGTH, WIDTH = 1.0, 0.1  # m, the strip
SPAN = 0.8                # m between the catenary's hooks
GRAVITY = 9.81

# Gauss–Seidel projection carries a chain's tension down it the slower the more links it
# has, so the residual stretch grows with the resolution at a fixed solve; substeps growing
# with the links keep it below the discretisation's error (at 100 substeps, 64 links were
# left stretched by 2.8e-4, adding 0.03 % to the sag, twice the discretisation's 0.013 %).
CATENARY_ITERATIONS = 4
CATENARY_SETTLE_S = 5.0   # s of simulated time; with the damping below the sag has settled
CATENARY_DAMPING = 0.1    # behavior.damping, a share per 18 ms: settles in ~2 s


def catenary_substeps(segments: int) -> int:
    return max(100, 6 * segments)


def _catenary_cases(material) -> list[Case]:
    c = catenary(SPAN, LENGTH)
    return [Case(f"span {SPAN:g} m, length {LENGTH:g} m", c.sag,
                 {"span": SPAN, "length": LENGTH, "a": c.a,
                  "pin_slope_deg": math.degrees(c.pin_slope)})]


def _measure_catenary(case: Case, segments: int, material, solver=None) -> Measurement:
    rows = particles_across(WIDTH, LENGTH, segments)
    pull = (LENGTH - SPAN) / 2
    scene = strip_scene(
        size=[LENGTH, WIDTH], resolution=[segments + 1, rows], material=material,
        pins=[{"cols": [0, 0], "offset": [pull, 0.0, 0.0]},
              {"cols": [-1, -1], "offset": [-pull, 0.0, 0.0]}],
        behavior={"solver": "pbd", "bending": False, "iterations": CATENARY_ITERATIONS,
                  "substeps": catenary_substeps(segments), "damping": CATENARY_DAMPING})
    sim = warmed_simulation(scene)
    frames = round(CATENARY_SETTLE_S * scene.behavior.frame_rate)
    wall = timed_frames(sim, frames)
    x = sim.state.x.reshape(rows, segments + 1, 3)
    lowest = 0.5 * (x[:, segments // 2, 1] + x[:, (segments + 1) // 2, 1])
    sag = float(np.mean(x[:, 0, 1] - lowest))
    stats = sim.stats()
    discrete = chain_sag(SPAN, LENGTH, segments)
    return Measurement(sag, {"wall_s": wall, "max_stretch": stats.max_stretch,
                             "discrete_chain": discrete, "solve_error": sag / discrete - 1,
                             "substeps": catenary_substeps(segments)})


CATENARY = Experiment(
    name="catenary",
    summary=f"a {LENGTH:g} m × {WIDTH:g} m strip hung by its short ends from hooks {SPAN:g} m "
            "apart: the sag (hooks to lowest point) against y = a·cosh(x/a)",
    quantity="sag", unit="m",
    resolution_meaning="links along the strip",
    default_resolutions=(8, 16, 32), min_resolution=4, tolerance=0.005,
    cases=_catenary_cases, measure=_measure_catenary,
    setup=f"pbd, bending off, {CATENARY_ITERATIONS} iterations, substeps max(100, 6·N), "
          f"{CATENARY_SETTLE_S:g} s settling at damping {CATENARY_DAMPING:g}")


# The swing: released from the first mode's shape, at rest, 2 cm at the tip (small: the
# chain's modes are those of small swings), undamped. Tethers off: they hold each particle
# within its flat-sheet distance of the top edge, which a hanging strip just reaches, and
# there their projection lengthened the period by 0.8 % at 16 links and 1.4 % at 32.
SWING_AMPLITUDE = 0.02    # m, at the tip
SWING_PERIODS = 4         # periods timed
SWING_ITERATIONS = 4
SWING_SUBSTEPS = 100


def _swing_cases(material) -> list[Case]:
    return [Case(f"length {LENGTH:g} m, g = {GRAVITY:g} m/s²",
                 hanging_chain_period(LENGTH, GRAVITY),
                 {"length": LENGTH, "omega1": 2 * math.pi / hanging_chain_period(LENGTH)})]


def first_mode(length: float, s: np.ndarray) -> np.ndarray:
    """The hanging chain's first mode at arc length s from the top: J₀(j₀,₁·√((L − s)/L)),
    1 at the free end, 0 at the top."""
    j = bessel_j0_zero(1)
    return np.array([bessel_j0(j * math.sqrt(max(0.0, (length - t) / length))) for t in s])


def zero_crossing_period(t: np.ndarray, u: np.ndarray) -> tuple[float, int]:
    """(period, crossings) of an oscillation u(t) from its sign changes, each placed by
    linear interpolation: consecutive crossings are half a period apart."""
    crossings = []
    for k in range(len(u) - 1):
        if u[k] * u[k + 1] < 0:
            crossings.append(t[k] - u[k] * (t[k + 1] - t[k]) / (u[k + 1] - u[k]))
    if len(crossings) < 3:
        return math.nan, len(crossings)
    return 2 * (crossings[-1] - crossings[0]) / (len(crossings) - 1), len(crossings)


def _measure_swing(case: Case, segments: int, material, solver=None) -> Measurement:
    cols = particles_across(WIDTH, LENGTH, segments)
    scene = strip_scene(
        size=[WIDTH, LENGTH], resolution=[cols, segments + 1], material=material,
        pins=[{"rows": [0, 0]}],
        behavior={"solver": "pbd", "bending": False, "tethers": False, "damping": 0.0,
                  "iterations": SWING_ITERATIONS, "substeps": SWING_SUBSTEPS})
    sim = warmed_simulation(scene)
    x = sim.state.x.reshape(segments + 1, cols, 3)
    top_y, top_z = float(x[0, 0, 1]), float(x[0, 0, 2])
    s = np.arange(segments + 1) * (LENGTH / segments)
    x[:, :, 1] = top_y - s[:, None]  # hanging straight down from the held top edge ...
    x[:, :, 2] = top_z + SWING_AMPLITUDE * first_mode(LENGTH, s)[:, None]  # ... bent as mode 1
    sim.state.x_prev[:] = sim.state.x
    times, tip = [0.0], [SWING_AMPLITUDE]

    def record(sim) -> None:
        times.append(sim.state.t)
        tip.append(float(sim.state.x.reshape(segments + 1, cols, 3)[-1, :, 2].mean() - top_z))

    frames = math.ceil((SWING_PERIODS + 0.5) * case.expected * scene.behavior.frame_rate)
    wall = timed_frames(sim, frames, record)
    period, crossings = zero_crossing_period(np.array(times), np.array(tip))
    discrete = 2 * math.pi / lumped_chain_omega(LENGTH, GRAVITY, segments)
    return Measurement(period, {"wall_s": wall, "crossings": crossings,
                                "discrete_chain": discrete, "solve_error": period / discrete - 1,
                                "max_stretch": sim.stats().max_stretch})


SWING = Experiment(
    name="swing",
    summary=f"a {LENGTH:g} m × {WIDTH:g} m strip hanging from its top edge, released from "
            "its first mode: the period against the hanging chain's 2π/ω₁, ω₁ = "
            "(j₀,₁/2)·√(g/L)",
    quantity="period", unit="s",
    resolution_meaning="links along the strip",
    default_resolutions=(8, 16, 32), min_resolution=4, tolerance=0.02,
    cases=_swing_cases, measure=_measure_swing,
    setup=f"pbd, bending and tethers off, {SWING_ITERATIONS} iterations, {SWING_SUBSTEPS} "
          f"substeps, no damping, {SWING_AMPLITUDE * 100:g} cm at the tip, "
          f"{SWING_PERIODS} periods timed")
