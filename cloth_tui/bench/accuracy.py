"""What accuracy costs in time: a work-precision study of the solvers and integrators.

The test scene (documented in docs/accuracy.md): an 8×8 sheet, 0.5 m, 0.2 kg, starting flat
and at rest, pinned at the two corners of one edge (particles (0,0) and (0,7)), swinging down
under gravity 9.81 m/s²; no floor, no damping, no spring damping, structural + shear + bending
springs of stiffness `stiffness`. The state at `t_end` is compared with a reference computed
by the springs solver with RK4 at a tiny timestep `ref_dt`.

Every run is driven substep by substep, not through the runner, and stopped where it blows
up (accuracy_runs.simulate, with the test scene and StudyConfig); the study never raises on
an unstable run.

Plain functions returning data; printing, JSON and plotting are in accuracy_cli.
"""

from __future__ import annotations

import dataclasses
import math
import time

import numpy as np

from ..sim.solvers import registry as solver_registry
from ..sim.solvers.springs.integrators import ORDERS
from .accuracy_physical import physical_calls, physical_study
from .accuracy_runs import (CHECK_INTERVAL, Run, StudyConfig, errors, simulate, study_model,
                            study_scene)

INTEGRATORS = tuple(ORDERS)           # springs integrators, in the order of the tables
# The position-based solvers compared with them: every registered solver of constraints.
CONSTRAINT_SOLVERS = solver_registry.Names(solves_constraints=True)
TIMING_REPEATS = 5                    # at most this many timings of one point (fastest kept)


# --- the study -------------------------------------------------------------------------------

def reference(cfg: StudyConfig) -> dict:
    """RK4 at ref_dt, and an estimate of its own error from a run at 2·ref_dt (Richardson:
    e(ref) ≈ |x(2h) − x(h)| / (2⁴ − 1))."""
    sc = study_scene(cfg, "springs", "rk4", cfg.ref_dt)
    model = study_model(sc)
    fine = simulate(sc, model, cfg.t_end)
    coarse = simulate(study_scene(cfg, "springs", "rk4", 2 * cfg.ref_dt), model, cfg.t_end)
    est = errors(coarse.x, fine.x)[0] / 15.0 if fine.stable and coarse.stable else math.nan
    return {"method": "rk4", "dt": cfg.ref_dt, "t_end": cfg.t_end, "x": fine.x,
            "error_estimate": est, "time": fine.wall / cfg.t_end,
            "stiffness": cfg.stiffness, "stable": fine.stable}


def point(cfg: StudyConfig, ref: dict, method: str, dt: float, iterations: int | None = None,
          stiffness: float | None = None) -> dict:
    """One run of the study, compared with the reference."""
    solver = method if method in CONSTRAINT_SOLVERS else "springs"
    sc = study_scene(cfg, solver, method if solver == "springs" else "verlet", dt,
                     iterations or 1, stiffness)
    model = study_model(sc)
    try:
        run = simulate(sc, model, cfg.t_end)
    except (FloatingPointError, OverflowError, ZeroDivisionError, ValueError):
        run = Run(None, False, 0.0, math.inf, math.nan, 0, 0.0)
    if run.stable:
        err, max_err = errors(run.x, ref["x"])
        # A cheap run is repeated and its fastest time kept (other processes share the cores).
        walls, cpus = [run.wall], [run.cpu]
        while sum(walls) < cfg.timing_budget and len(walls) < TIMING_REPEATS:
            again = simulate(sc, model, cfg.t_end)
            walls.append(again.wall)
            cpus.append(again.cpu)
        wall, cpu = min(walls), min(cpus)
    else:
        err = max_err = wall = cpu = math.nan
    return {"method": method, "dt": dt, "iterations": iterations, "error": err,
            "max_error": max_err, "time": wall / cfg.t_end, "cpu_time": cpu / cfg.t_end,
            "stable": run.stable, "stretch": run.stretch, "energy_drift": run.energy_drift}


def warm_up(cfg: StudyConfig) -> None:
    """Compile (or load the cached) kernels of every method, so no run pays for it."""
    tiny = dataclasses.replace(cfg, t_end=4 * CHECK_INTERVAL, timing_budget=0.0)
    ref = {"x": np.zeros((cfg.n * cfg.n, 3))}
    for m in INTEGRATORS + tuple(CONSTRAINT_SOLVERS):
        point(tiny, ref, m, 1e-3, 2)


def measured_order(points: list[dict], floor: float, ceiling: float) -> dict:
    """Slope of log(error) against log(dt) over the stable asymptotic range: the finest
    consecutive stable points whose error is above `floor` (10× the reference's error) and
    below `ceiling`, at most four of them, least squares."""
    pts = sorted((p for p in points if p["stable"] and floor < p["error"] < ceiling),
                 key=lambda p: p["dt"])
    pts = pts[:4]
    if len(pts) < 2:
        return {"order": math.nan, "dt_range": None, "points": len(pts)}
    lx = np.log([p["dt"] for p in pts])
    ly = np.log([p["error"] for p in pts])
    slope = float(np.polyfit(lx, ly, 1)[0])
    return {"order": slope, "dt_range": [pts[0]["dt"], pts[-1]["dt"]], "points": len(pts)}


def is_stable(cfg: StudyConfig, integrator: str, dt: float, stiffness: float) -> bool:
    sc = study_scene(cfg, "springs", integrator, dt, stiffness=stiffness)
    try:
        return simulate(sc, study_model(sc), cfg.stability_t_end).stable
    except (FloatingPointError, OverflowError, ZeroDivisionError, ValueError):
        return False


def largest_stable_dt(cfg: StudyConfig, integrator: str, stiffness: float) -> dict:
    """Bisection in log dt over `stability_range` for the largest dt whose run to
    stability_t_end stays stable. Returns the bracket; `at_least` when even the largest dt
    of the range is stable (unconditionally stable here), `below` when none is."""
    lo, hi = cfg.stability_range
    if is_stable(cfg, integrator, hi, stiffness):
        return {"dt": hi, "bracket": [hi, hi], "note": "at_least"}
    if not is_stable(cfg, integrator, lo, stiffness):
        return {"dt": lo, "bracket": [0.0, lo], "note": "below"}
    for _ in range(cfg.stability_bisections):
        mid = math.sqrt(lo * hi)
        if is_stable(cfg, integrator, mid, stiffness):
            lo = mid
        else:
            hi = mid
    return {"dt": lo, "bracket": [lo, hi], "note": ""}


def stability_calls(cfg: StudyConfig) -> list[tuple]:
    """The stability map's runs: a bisection per (integrator, stiffness)."""
    return [(largest_stable_dt, (cfg, integ, k))
            for integ in INTEGRATORS for k in cfg.stability_stiffness]


def stability_map(cfg: StudyConfig, limits: list | None = None) -> dict:
    """Largest stable timestep of each springs integrator at each of three stiffnesses,
    and ω0 = √(k/m) of each stiffness (m of an interior particle; edges have ½ of it and
    corners ¼): a limit dt·ω0 that stays the same across stiffnesses means the limit scales
    as 1/√k. `limits`: the results of stability_calls, if already run."""
    limits = iter(limits if limits is not None else run_serially(stability_calls(cfg)))
    m = cfg.mass / (cfg.n - 1) ** 2  # an interior particle's (masses by area)
    out = {"t_end": cfg.stability_t_end, "range": list(cfg.stability_range),
           "stiffness": list(cfg.stability_stiffness), "methods": {}}
    for integ in INTEGRATORS:
        out["methods"][integ] = {f"{k:g}": next(limits) for k in cfg.stability_stiffness}
    out["omega0"] = {f"{k:g}": math.sqrt(k / m) for k in cfg.stability_stiffness}
    return out


def _centre(n: int) -> list[int]:
    return [(n // 2 - 1) * n + n // 2 - 1, (n // 2 - 1) * n + n // 2,
            (n // 2) * n + n // 2 - 1, (n // 2) * n + n // 2] if n % 2 == 0 else [(n * n) // 2]


def sag_run(cfg: StudyConfig, solver: str, iterations: int) -> float:
    """Settled sag of one sag-study run (m); `springs` is the converged comparison."""
    dt = 1.0 / (60 * cfg.sag_substeps)
    if solver == "springs":
        sc = study_scene(cfg, "springs", "implicit_euler", dt, stiffness=1.0 / cfg.sag_compliance,
                         damping=cfg.sag_damping, pinned="corners")
    else:
        sc = study_scene(cfg, solver, "verlet", dt, iterations, compliance=cfg.sag_compliance,
                         damping=cfg.sag_damping, pinned="corners")
    run = simulate(sc, study_model(sc, "corners"), cfg.sag_t_end)
    return -float(run.x[_centre(cfg.n), 1].mean()) if run.stable else math.nan


def sag_calls(cfg: StudyConfig) -> list[tuple]:
    return [(sag_run, (cfg, solver, it)) for solver in CONSTRAINT_SOLVERS
            for it in cfg.sag_iterations] + [(sag_run, (cfg, "springs", 0))]


def sag_study(cfg: StudyConfig, sags: list | None = None) -> dict:
    """Settled sag (drop of the centre) of the sheet pinned at its four corners, for pbd and
    xpbd at each of `sag_iterations`; damping `sag_damping` while settling for `sag_t_end`.
    xpbd uses compliance `sag_compliance` (stiffness 1/α); the springs solver with that
    stiffness and implicit Euler gives the converged answer for comparison. `sags`: the
    results of sag_calls, if already run."""
    sags = iter(sags if sags is not None else run_serially(sag_calls(cfg)))
    rows = {solver: {str(it): next(sags) for it in cfg.sag_iterations}
            for solver in CONSTRAINT_SOLVERS}
    spread = {s: (max(v.values()) - min(v.values())) for s, v in rows.items()}
    return {"iterations": list(cfg.sag_iterations), "sag": rows,
            "spread": spread,
            "springs_implicit_euler": next(sags),
            "compliance": cfg.sag_compliance, "dt": 1.0 / (60 * cfg.sag_substeps),
            "t_end": cfg.sag_t_end, "damping": cfg.sag_damping}


def run_serially(calls: list[tuple]) -> list:
    return [fn(*args) for fn, args in calls]


_warmed = False  # this process has compiled the kernels (a Dask worker keeps them warm)


def warm_then(fn, *args):
    """fn(*args) after compiling every method's kernels once per process, so that no timed
    run pays for it: how a Dask worker runs the study's tasks."""
    global _warmed
    if not _warmed:
        warm_up(StudyConfig())
        _warmed = True
    return fn(*args)


def run_study(cfg: StudyConfig, progress=None, run_all=None) -> dict:
    """The whole study: reference, work-precision points, orders, stability map, sag, and
    the physical reference (a clamped strip against the elastica, accuracy_physical).
    `run_all(calls)` runs a list of (function, args) and returns the results in order:
    serially in this process by default, or as tasks on Dask (`accuracy --workers`); the
    runs are independent, and each gives the same numbers wherever it runs."""
    say = progress or (lambda msg: None)
    t_start = time.perf_counter()
    if run_all is None:
        say("compiling kernels")
        warm_up(cfg)
        run_all = run_serially
    say(f"reference: rk4 at dt = {cfg.ref_dt:.3g} s")
    ref, = run_all([(reference, (cfg,))])
    point_calls = [(point, (cfg, ref, integ, dt))
                   for integ in INTEGRATORS for dt in cfg.ladders.get(integ, ())]
    point_calls += [(point, (cfg, ref, solver, dt, it)) for solver in CONSTRAINT_SOLVERS
                    for it in cfg.pbd_iterations for dt in cfg.pbd_dts]
    n_sag, cantilever = len(sag_calls(cfg)), physical_calls(cfg.cantilever_links)
    calls = point_calls + stability_calls(cfg) + sag_calls(cfg) + cantilever
    say(f"{len(point_calls)} work-precision points, stability map, sag study, physical "
        f"reference: {len(calls)} runs")
    results = run_all(calls)
    points = results[:len(point_calls)]
    n_stab = len(stability_calls(cfg))
    stab = stability_map(cfg, results[len(point_calls):len(point_calls) + n_stab])
    first_sag = len(point_calls) + n_stab
    sag = sag_study(cfg, results[first_sag:first_sag + n_sag])
    physical = physical_study(cfg.cantilever_links, results[first_sag + n_sag:])
    floor = 10.0 * ref["error_estimate"] if math.isfinite(ref["error_estimate"]) else 0.0
    ceiling = 0.02 * cfg.size
    orders = {}
    for integ in INTEGRATORS:
        o = measured_order([p for p in points if p["method"] == integ], floor, ceiling)
        o["theory"] = ORDERS[integ]
        orders[integ] = o
    reference_out = {k: v for k, v in ref.items() if k != "x"}
    reference_out["error_floor"] = floor
    return {"scene": describe(cfg), "reference": reference_out, "points": points,
            "orders": orders, "stability": stab, "sag": sag, "physical": physical,
            "elapsed": time.perf_counter() - t_start}


def describe(cfg: StudyConfig) -> dict:
    return {"n": cfg.n, "size": cfg.size, "mass": cfg.mass, "gravity": cfg.gravity,
            "stiffness": cfg.stiffness, "t_end": cfg.t_end, "pinned": "two corners (0,0), (0,n−1)",
            "floor": False, "damping": 0.0, "spring_damping": 0.0,
            "xpbd_compliance": 1.0 / cfg.stiffness}
