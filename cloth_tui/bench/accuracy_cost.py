"""The cost of accuracy: what each solver spends to meet the default accuracy on the original's
sheet (the built-in scene `original`: pinned at its corners, no fabric) as the sheet grows.

For each solver and sheet size n that scene (adaptive substeps, the default error
tolerance) runs `frames` frames from rest, `repeats` times from a fresh sheet. Reported:
the work it needed (substeps per frame the controller ran, redone frames included, and
substeps × passes per substep, hpbd's coarse levels counted as the fine passes their
projections equal), whether every frame met the tolerance, and wall ms per
simulated frame (median over the repeats, with the slowest and fastest). The growth exponent
is the least-squares slope of log(ms per frame) against log(particles): 1 is linear in the
particles, 1.5 is the n³ of a Gauss-Seidel solve whose passes carry a correction one
particle each."""

from __future__ import annotations

import math
import statistics
import time

from ..pin_groups import grid_of
from ..sim.solvers import registry as solver_registry


def solver_runs() -> tuple[tuple[str, dict], ...]:
    """(label, the scene keys it sets) of every registered solver of constraints, the
    original scene's own (the schema's default) first."""
    own = solver_registry.DEFAULT
    rest = [n for n in solver_registry.names(solves_constraints=True) if n != own]
    return ((own, {}),) + tuple((n, {"behavior.solver": n}) for n in rest)
SIZES = (32, 64, 128, 256)
QUICK_SIZES = (32, 64)


def cost_scene(n: int, overrides: dict):
    """The original scene at n×n with a solver's keys."""
    from ..scene_files import load
    return load("original").with_values({"cloth.resolution": n, **overrides})


def run_once(scene, frames: int) -> dict:
    """One run of `frames` frames from a fresh sheet: its wall time and work."""
    from ..sim.run.runner import Simulation

    sim = Simulation(scene)
    met = True
    worst = 0.0
    t0 = time.perf_counter()
    for _ in range(frames):
        sim.advance_frame()
        met = met and sim.control.met
        worst = max(worst, sim.frame_error)
    wall = time.perf_counter() - t0
    return {"wall_s": wall, "substeps_run": sim.substeps_run, "met": met and not sim.halted,
            "worst_error": worst, "halted": sim.halted,
            "passes": _passes(sim)}


def _passes(sim) -> float:
    """Constraint passes per substep, a hierarchy's coarse levels counted in fine passes."""
    solver = sim.step.solver
    return 0.0 if solver is None else solver.passes_per_substep


def bench_cost(n: int, overrides: dict, frames: int, repeats: int,
               scene_for=cost_scene) -> dict:
    """`frames` frames of `scene_for(n, overrides)`, `repeats` times from a fresh sheet."""
    scene = scene_for(n, overrides)
    run_once(scene, 1)  # compile or load the kernels, outside the timing
    runs = [run_once(scene, frames) for _ in range(repeats)]
    ms = [1e3 * r["wall_s"] / frames for r in runs]
    substeps = statistics.mean(r["substeps_run"] for r in runs) / frames
    return {"n": n, "particles": math.prod(grid_of(scene.cloth)), "frames": frames,
            "repeats": repeats,
            "substeps_per_frame": substeps,
            "passes_per_substep": runs[0]["passes"],
            "work_per_frame": substeps * runs[0]["passes"],
            "met": all(r["met"] for r in runs),
            "worst_error": max(r["worst_error"] for r in runs),
            "tolerance": scene.behavior.error_tolerance,
            "ms_per_frame": statistics.median(ms), "ms_min": min(ms), "ms_max": max(ms),
            "frames_per_s": 1e3 / statistics.median(ms)}


def growth_exponent(rows: list[dict], key: str = "ms_per_frame", lo: int = 0,
                    hi: int = 1 << 30) -> float | None:
    """Least-squares slope of log(key) against log(particles) over the rows with lo ≤ n ≤ hi;
    None with fewer than two."""
    pts = [(math.log(r["particles"]), math.log(r[key])) for r in rows
           if lo <= r["n"] <= hi and r[key] > 0]
    if len(pts) < 2:
        return None
    mx = sum(p[0] for p in pts) / len(pts)
    my = sum(p[1] for p in pts) / len(pts)
    sxx = sum((p[0] - mx) ** 2 for p in pts)
    return sum((p[0] - mx) * (p[1] - my) for p in pts) / sxx if sxx else None


def bench_accuracy_cost(sizes=None, quick: bool = False, progress=lambda msg: None,
                        solvers=None) -> dict:
    """Every solver at every size, side by side, with the fitted growth exponents."""
    sizes = list(sizes or (QUICK_SIZES if quick else SIZES))
    frames, repeats = (12, 2) if quick else (60, 3)
    out = []
    for label, overrides in solvers or solver_runs():
        rows = []
        for n in sizes:
            progress(f"cost of accuracy: {label}, n={n}")
            rows.append(bench_cost(n, overrides, frames, repeats))
        out.append({"solver": label, "keys": overrides, "rows": rows,
                    "exponent": growth_exponent(rows),
                    "exponent_64_256": growth_exponent(rows, lo=64, hi=256)
                    if {64, 256} <= set(sizes) else None,
                    "work_exponent": growth_exponent(rows, key="work_per_frame")})
    return {"sizes": sizes, "frames": frames, "repeats": repeats, "solvers": out}


def format_cost(r: dict) -> list[str]:
    out = ["", f"Cost of accuracy: the original scene at the default tolerance (adaptive), "
               f"{r['frames']} frames from rest, {r['repeats']} runs; work = substeps per "
               f"frame (redone frames included) × passes per substep; ms per simulated frame: "
               f"median [fastest–slowest run]",
           f"  {'solver':<22} {'n':>5} {'substeps':>9} {'work':>8} {'met':>4} "
           f"{'worst error':>13} | {'ms per frame':>25} | {'frames/s':>8}"]
    for s in r["solvers"]:
        for row in s["rows"]:
            ms = (f"{row['ms_per_frame']:.2f} [{row['ms_min']:.2f}–{row['ms_max']:.2f}]")
            out.append(f"  {s['solver']:<22} {row['n']:>5} {row['substeps_per_frame']:>9.1f} "
                       f"{row['work_per_frame']:>8.0f} {'yes' if row['met'] else 'NO':>4} "
                       f"{row['worst_error']:>13.4f} | {ms:>25} | "
                       f"{row['frames_per_s']:>8.1f}")
        fits = [f"time ∝ particles^{s['exponent']:.2f}" if s["exponent"] is not None else None,
                f"from 64² to 256² ^{s['exponent_64_256']:.2f}"
                if s["exponent_64_256"] is not None else None,
                f"work ∝ particles^{s['work_exponent']:.2f}"
                if s["work_exponent"] is not None else None]
        if any(fits):
            out.append(f"  {'':<22} growth: " + ", ".join(f for f in fits if f))
    return out
