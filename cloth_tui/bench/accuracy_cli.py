"""`cloth-tui accuracy [--quick] [--json] [--plot OUT.png] [--workers N | --scheduler ADDR]`:
run the study of bench/accuracy.py (serially, or its runs as tasks on Dask) and print it as
tables, as one JSON object, and/or draw the work-precision diagram."""

from __future__ import annotations

import json
import math
import sys
from pathlib import Path

from ..usage import UsageError, check_output_path
from . import accuracy
from .accuracy_physical import format_physical

METHOD_STYLE = {  # colour, marker
    "explicit_euler": ("tab:red", "o"), "symplectic_euler": ("tab:cyan", "s"),
    "verlet": ("tab:green", "^"), "midpoint": ("tab:olive", "v"), "rk4": ("tab:blue", "D"),
    "implicit_euler": ("tab:purple", "P"),
}
# Position-based solvers: a colour map each, light to dark with the iterations.
SOLVER_SHADES = ("Greys", "Oranges", "Greens", "Purples", "Blues")


class PlotError(Exception):
    pass


def _num(v):
    """JSON has no NaN/inf: null instead."""
    if isinstance(v, float) and not math.isfinite(v):
        return None
    if isinstance(v, dict):
        return {k: _num(x) for k, x in v.items()}
    if isinstance(v, (list, tuple)):
        return [_num(x) for x in v]
    return v


def _check_plot_path(path: Path) -> None:
    if path.suffix.lower() != ".png":
        raise UsageError(f"{path}: the plot is a PNG; use a .png file name")
    check_output_path(path, (".png",))
    try:
        import matplotlib  # noqa: F401
    except ImportError:
        raise UsageError("--plot needs matplotlib: pip install 'cloth-tui[plot]'") from None


def run_accuracy(args) -> int:
    plot = Path(args.plot) if getattr(args, "plot", None) else None
    if plot is not None:
        _check_plot_path(plot)
    cfg = accuracy.StudyConfig.quick() if args.quick else accuracy.StudyConfig.full()
    progress = None if args.json else (lambda msg: print(f"… {msg}", file=sys.stderr,
                                                        flush=True))
    workers, scheduler = getattr(args, "workers", None), getattr(args, "scheduler", None)
    if workers or scheduler:
        result = _run_on_dask(cfg, progress, workers or 1, scheduler)
    else:
        result = accuracy.run_study(cfg, progress)
    if plot is not None:
        plot_work_precision(result, plot)
    if args.json:
        print(json.dumps(_num(result)))
    else:
        print(format_report(result))
        if plot is not None:
            print(f"\nwork-precision diagram written to {plot}")
    return 0


def _run_on_dask(cfg, progress, workers: int, scheduler: str | None) -> dict:
    """The same study with its runs as tasks on Dask (wedge.engine): the same results as the
    serial run's, the timings measured on the workers."""
    from ..interrupt import Progress
    from ..wedge.engine import Engine, require_dask

    require_dask("accuracy")
    with Engine(workers, scheduler) as engine:
        def run_all(calls):
            bar = Progress(len(calls), progress is not None and sys.stderr.isatty(), "runs")
            done = []
            results = engine.map(accuracy.warm_then, [(fn, *a) for fn, a in calls],
                                 lambda i, r: (done.append(i), bar.show(len(done))))
            bar.end()
            return results
        return accuracy.run_study(cfg, progress, run_all)


# --- text ------------------------------------------------------------------------------------

def _g(v, fmt=".3g"):
    return "—" if v is None or (isinstance(v, float) and not math.isfinite(v)) else format(v, fmt)


def format_report(r: dict) -> str:
    s, ref = r["scene"], r["reference"]
    out = [
        f"Accuracy study: {s['n']}×{s['n']} sheet, {s['size']} m, {s['mass']} kg, pinned at two "
        f"corners, gravity {s['gravity']} m/s², no floor, no damping; springs k = "
        f"{s['stiffness']:g} N/m (xpbd α = {s['xpbd_compliance']:g} m/N); end time "
        f"{s['t_end']} s.",
        f"Reference: rk4 at dt = {ref['dt']:.3g} s (its own error ≈ {_g(ref['error_estimate'])} m;"
        f" errors below {_g(ref['error_floor'])} m are not used for orders).",
        "",
        f"{'method':<17}{'dt (s)':>10}{'iter':>6}{'RMS err (m)':>13}{'max err (m)':>13}"
        f"{'wall s/sim s':>14}{'stretch':>10}{'E drift':>10}  stable",
    ]
    for p in r["points"]:
        out.append(f"{p['method']:<17}{p['dt']:>10.3g}{p['iterations'] or '':>6}"
                   f"{_g(p['error']):>13}{_g(p['max_error']):>13}{_g(p['time']):>14}"
                   f"{_g(p['stretch']):>10}{_g(p['energy_drift'], '+.2g'):>10}  "
                   f"{'yes' if p['stable'] else 'NO'}")
    out += ["", "Measured order (slope of log RMS error vs log dt, finest stable points):",
            f"{'integrator':<17}{'theory':>7}{'measured':>10}  dt range (s)"]
    for m, o in r["orders"].items():
        rng = o["dt_range"]
        out.append(f"{m:<17}{o['theory']:>7}{_g(o['order'], '.2f'):>10}  "
                   + (f"{rng[0]:.3g} – {rng[1]:.3g}" if rng else "—"))
    st = r["stability"]
    ks = [f"{k:g}" for k in st["stiffness"]]
    out += ["", f"Stability map: largest stable dt (s) over a {st['t_end']} s run "
                f"(bisection in [{st['range'][0]:.3g}, {st['range'][1]:.3g}] s)",
            f"{'integrator':<17}" + "".join(f"{'k = ' + k + ' N/m':>16}" for k in ks)]
    for m, row in st["methods"].items():
        cells = []
        for k in ks:
            c = row[k]
            txt = {"at_least": f"≥ {c['dt']:.3g}", "below": f"< {c['dt']:.3g}"}.get(
                c["note"], f"{c['dt']:.3g}")
            cells.append(f"{txt:>16}")
        out.append(f"{m:<17}" + "".join(cells))
    out.append(f"{'ω0 = √(k/m) 1/s':<17}" + "".join(f"{st['omega0'][k]:>16.0f}" for k in ks))
    sg = r["sag"]
    out += ["", f"Settled sag (m) of the centre, sheet pinned at 4 corners, dt = {sg['dt']:.3g} s,"
                f" {sg['t_end']} s settling (xpbd α = {sg['compliance']:g} m/N):",
            f"{'iterations':<12}" + "".join(f"{i:>10}" for i in sg["iterations"])
            + f"{'spread':>10}"]
    for solver in sg["sag"]:
        out.append(f"{solver:<12}" + "".join(f"{sg['sag'][solver][str(i)]:>10.4f}"
                                             for i in sg["iterations"])
                   + f"{sg['spread'][solver]:>10.4f}")
    out.append(f"springs k = 1/α, implicit Euler (converged): "
               f"{_g(sg['springs_implicit_euler'], '.4f')} m")
    out += [""] + format_physical(r["physical"])
    out.append(f"\nstudy time {r['elapsed']:.1f} s")
    return "\n".join(out)


# --- plot ------------------------------------------------------------------------------------

def plot_work_precision(r: dict, path: Path) -> None:
    """Error against wall time per simulated second, log-log, one line per method (pbd and
    xpbd: one per iteration count); unstable runs marked × at the top edge."""
    import matplotlib
    matplotlib.use("Agg")
    import matplotlib.pyplot as plt

    from ..util import atomic_write

    physical = r.get("physical", {}).get("points")
    if physical:
        fig, (ax, phys) = plt.subplots(1, 2, figsize=(14, 6), dpi=110,
                                       gridspec_kw={"width_ratios": [1.7, 1]})
        plot_physical(r["physical"], phys)
    else:
        fig, ax = plt.subplots(figsize=(8.5, 6), dpi=110)
    groups: dict = {}
    for p in r["points"]:
        label = p["method"] + (f" ×{p['iterations']} it" if p["iterations"] else "")
        groups.setdefault((p["method"], label), []).append(p)
    stable_err = [p["error"] for p in r["points"] if p["stable"]]
    top = max(stable_err) * 3 if stable_err else 1.0
    stable_t = [p["time"] for p in r["points"] if p["stable"]]
    for (method, label), pts in groups.items():
        color, marker = METHOD_STYLE.get(method, ("black", "o"))
        dashed = False
        if pts[0]["iterations"]:  # a position-based solver: shaded by its iterations
            its = sorted({q["iterations"] for q in r["points"] if q["method"] == method})
            shade = 0.4 + 0.55 * its.index(pts[0]["iterations"]) / max(1, len(its) - 1)
            solvers = list(r["sag"]["sag"])  # the position-based solvers, in the study's order
            shades = SOLVER_SHADES[solvers.index(method) % len(SOLVER_SHADES)]
            color = plt.get_cmap(shades)(shade)
            dashed = solvers.index(method) % 2 == 0
        ok = sorted((p for p in pts if p["stable"]), key=lambda p: -p["dt"])
        if ok:
            ax.plot([p["time"] for p in ok], [p["error"] for p in ok], marker=marker,
                    color=color, ls="--" if dashed else "-", label=label, ms=5)
        bad = [p for p in pts if not p["stable"]]
        if bad:
            # An unstable run has no error and no meaningful time: × at the top edge, placed
            # by the wall time its timestep would cost (steps per simulated second × the cost
            # per step of the method's stable runs).
            per_step = [p["time"] * p["dt"] for p in ok]
            c = float(sum(per_step) / len(per_step)) if per_step else (
                min(stable_t) if stable_t else 1e-3) * 1e-3
            ax.plot([c / p["dt"] for p in bad], [top] * len(bad), ls="none", marker="x",
                    color=color, ms=9, mew=2, label=f"{method} unstable" if not ok else None)
    ax.set_xscale("log")
    ax.set_yscale("log")
    ax.axhline(top, color="0.8", lw=0.8)
    ax.text(ax.get_xlim()[0], top, " × = unstable run", va="bottom", fontsize=8, color="0.3")
    ax.set_xlabel("wall time per simulated second (s)")
    ax.set_ylabel(f"RMS position error at t = {r['scene']['t_end']} s (m)")
    o = r["orders"]
    ax.set_title("Work-precision: " + ", ".join(f"{m.replace('_', ' ')} {_g(v['order'], '.2f')}"
                                                for m, v in o.items()), fontsize=8)
    fig.suptitle(f"cloth-tui accuracy: {r['scene']['n']}×{r['scene']['n']} sheet, "
                 f"k = {r['scene']['stiffness']:g} N/m, reference rk4 dt = "
                 f"{r['reference']['dt']:.2g} s", fontsize=10)
    ax.grid(True, which="both", alpha=0.25)
    ax.legend(fontsize=7, ncol=2, loc="lower left")
    fig.tight_layout()
    with atomic_write(Path(path)) as fh:
        fig.savefig(fh, format="png")
    plt.close(fig)


def plot_physical(p: dict, ax) -> None:
    """|error| of the clamped strip's tip drop against wall time, one line per solver, each
    point labelled with its resolution."""
    by_solver: dict = {}
    for q in p["points"]:
        by_solver.setdefault(q["solver"], []).append(q)
    for solver, pts in by_solver.items():
        color, marker = METHOD_STYLE.get(solver, ("black", "o"))
        pts = sorted(pts, key=lambda q: q["links"])
        ax.plot([q["wall_s"] for q in pts], [abs(q["error"]) for q in pts], marker=marker,
                color=color, label=solver)
        for q in pts:
            ax.annotate(f"L/{q['links']}", (q["wall_s"], abs(q["error"])), fontsize=7,
                        textcoords="offset points", xytext=(4, 4))
    ax.set_xscale("log")
    ax.set_yscale("log")
    ax.grid(True, which="both", alpha=0.25)
    ax.set_xlabel("wall time of the settling run (s)")
    ax.set_ylabel("|relative error| of the tip drop δ/L")
    ax.set_title(f"Physical reference: {p['preset']} strip at wL³/B = {p['load']:g} "
                 f"against the elastica", fontsize=8)
    ax.legend(fontsize=7)
