"""`cloth-tui lab TEST [--material NAME] [--solver NAME] [--resolutions N,N,…] [--json]
[--plot OUT.png]`:
run one of the lab's tests and print measured against expected at each resolution, the
error, the fitted convergence order and the wall time; or one JSON object; and/or draw the
error against resolution and against wall time."""

from __future__ import annotations

import json
import math
import sys
from pathlib import Path

from ..usage import UsageError, check_output_path
from .strips import specimen_problem
from .study import LabError

# the extras a test's runs report, shown as columns when present: key → (header, format)
EXTRA_COLUMNS = {
    "solve_error": ("vs discrete", "+.3%"),   # against the exact equilibrium of the grid
    "max_stretch": ("stretch", ".1e"),
    "substeps": ("substeps", "d"),
    "crossings": ("crossings", "d"),
    "overhang": ("overhang (m)", ".5g"),
    "runs": ("runs", "d"),
    "folds": ("folds", "d"),
    "shadow_cm2": ("shadow (cm²)", ".1f"),
    "settled_s": ("settled (s)", ".2f"),
}


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


class _ProgressLine:
    """One updating stderr line, on a terminal only; a compile notice ends its own line
    first. `end()` ends a line left open, so what follows (an error) starts a fresh one."""

    def __init__(self, test: str, notice, enabled: bool) -> None:
        self.test, self.notice, self.enabled = test, notice, enabled
        self.open = False

    def __call__(self, done: int, total: int, what: str) -> None:
        if not self.enabled:
            return
        self.notice.finish()
        text = (f"lab {self.test}: {done}/{total} runs" +
                (f", now {what}…" if done < total else " done"))
        self.open = done < total
        sys.stderr.write(f"\r{text}\x1b[K" + ("" if self.open else "\n"))
        sys.stderr.flush()

    def end(self) -> None:
        if self.open:
            sys.stderr.write("\n")
            sys.stderr.flush()
            self.open = False


def _refuse_material(experiment, material_name: str | None) -> None:
    """A test whose result no material changes (catenary, swing: only mass and length,
    and the sag and period are the same for any mass) refuses --material rather than name a
    fabric in its report that played no part."""
    if material_name is not None and not experiment.solvers:
        raise UsageError(f"--material: {experiment.name} measures a strip without bending "
                         f"stiffness, the same for every fabric; --material is for the "
                         f"tests of a material (cantilever, peirce, drape)")


def check_resolutions(experiment, resolutions: list[int], material, solver) -> None:
    """Refuse, before any run, a resolution whose specimen the scene format cannot hold (the
    substeps a fine strip needs, the pins of a fine disc): in the user's terms, N and the
    range this test runs with this material, rather than a scene key the user never set,
    after the coarser resolutions have run for minutes."""
    problems = {n: specimen_problem(experiment, n, material, solver) for n in resolutions}
    bad = [n for n in resolutions if problems[n]]
    if not bad:
        return
    lo, hi = experiment.min_resolution, bad[0] - 1  # the largest N that runs: bisection,
    while lo <= hi:                                 # the specimen's needs grow with N
        mid = (lo + hi) // 2
        if specimen_problem(experiment, mid, material, solver):
            hi = mid - 1
        else:
            lo = mid + 1
    fabric = f" with {material.preset}" if material is not None and material.preset else ""
    runs = (f"runs N = {experiment.min_resolution}–{hi} ({experiment.resolution_meaning})"
            if hi >= experiment.min_resolution else "runs at no resolution")
    raise UsageError(f"--resolutions: {experiment.name}{fabric} {runs}; at N = {bad[0]} its "
                     f"specimen cannot be built ({problems[bad[0]]})")


def run_lab(args) -> int:
    from . import registry, study
    from .fit_cli import refuse_fit_flags, run_fit

    if args.test == "fit":
        return run_fit(args)
    refuse_fit_flags(args)
    try:
        experiment = registry.experiment(args.test)
        _refuse_material(experiment, args.material)
        resolutions = (study.parse_resolutions(args.resolutions, experiment)
                       if args.resolutions else list(experiment.default_resolutions))
        material = study.lab_material(args.material)
        solver = study.check_solver(experiment, args.solver)
    except LabError as e:
        raise UsageError(str(e)) from None
    plot = Path(args.plot) if args.plot else None
    if plot is not None:
        _check_plot_path(plot)
    check_resolutions(experiment, resolutions, material, solver)
    from ..compile_notice import CompileNotice

    live = sys.stderr.isatty()
    with CompileNotice(sys.stderr, live) as notice:
        progress = _ProgressLine(experiment.name, notice, live)
        try:
            result = study.run(experiment, resolutions, material, progress, solver)
        except LabError as e:
            raise UsageError(str(e)) from None
        finally:  # an error or Ctrl+C is said on a line of its own
            progress.end()
    if plot is not None:
        (experiment.plot or plot_convergence)(result, plot)
    if args.json:
        print(json.dumps(_num(result)))
    else:
        print(format_report(result))
        if plot is not None:
            print(f"\n{'plot' if experiment.plot else 'convergence plot'} written to {plot}")
    return 0


# --- text ------------------------------------------------------------------------------------

def _g(v, fmt=".6g"):
    if v is None or (isinstance(v, float) and not math.isfinite(v)):
        return "—"
    return format(v, fmt)


def format_report(r: dict) -> str:
    unit = r["unit"]
    m = r["material"]
    out = [f"Textile lab · {r['test']}: {r['summary']}."]
    if m:
        out.append(f"Material {m['preset']}: {m['areal_density'] * 1e3:g} g/m², stretch "
                   f"{m['stretch'][0]:g} / {m['stretch'][1]:g} N/m, shear {m['shear']:g} N/m, "
                   f"bending {m['bending'] * 1e6:g} µN·m.")
    out.append(f"Solve: {r['setup']}. N = {r['resolution_meaning']}.")
    bound = f"within {r['tolerance'] * 100:g} %" if r["tolerance"] is not None else ""
    for case in r["cases"]:
        extras = [k for k in EXTRA_COLUMNS if any(k in p for p in case["points"])]
        expected = case["expected"]
        out += ["", f"{case['label']}: expected {r['quantity']} "
                    f"{_g(expected)}{' ' + unit if unit else ''} (computed)"
                if expected is not None
                else f"{case['label']}: (a report; no analytic value)"]
        measured = "measured" + (f" ({unit})" if unit else "")
        header = (f"{'N':>5}{measured:>16}" + (f"{'error':>11}" if expected is not None else "")
                  + (f"{bound:>14}" if bound else "") + f"{'wall (s)':>10}"
                  + "".join(f"{EXTRA_COLUMNS[k][0]:>13}" for k in extras))
        out.append(header)
        for p in case["points"]:
            err = p["error"]
            ok = ("yes" if err is not None and abs(err) <= r["tolerance"] else "NO") \
                if bound else ""
            row = (f"{p['resolution']:>5}{_g(p['measured']):>16}"
                   + (f"{_g(err, '+.3%'):>11}" if expected is not None else "")
                   + (f"{ok:>14}" if bound else "") + f"{p['wall_s']:>10.2f}")
            for k in extras:
                row += f"{_g(p.get(k), EXTRA_COLUMNS[k][1]):>13}"
            out.append(row)
        if expected is not None:
            out.append(f"convergence order (error ∝ hᵖ, least squares): "
                       f"p = {_g(case['order'], '.2f')}")
    out.append(f"\nlab time {r['elapsed_s']:.1f} s")
    return "\n".join(out)


# --- plot ------------------------------------------------------------------------------------

def plot_convergence(r: dict, path: Path) -> None:
    """|error| against resolution and against wall time, log-log, one line per case; the
    bound as a dashed line and an h² slope for reference. A report (no expected values)
    plots its measured values instead."""
    import matplotlib
    matplotlib.use("Agg")
    import matplotlib.pyplot as plt

    fig, (by_n, by_wall) = plt.subplots(1, 2, figsize=(10, 4.5), dpi=110)
    if all(case["expected"] is None for case in r["cases"]):
        _plot_report(r, by_n, by_wall)
        return _save(fig, r, path)
    for case in r["cases"]:
        pts = [p for p in case["points"] if p["error"] not in (None, 0.0)
               and math.isfinite(p["error"])]
        if not pts:
            continue
        label = case["label"] + (f" (p = {case['order']:.2f})" if case["order"] else "")
        errs = [abs(p["error"]) for p in pts]
        by_n.plot([p["resolution"] for p in pts], errs, "o-", label=label)
        by_wall.plot([p["wall_s"] for p in pts], errs, "o-", label=label)
    ns = sorted({p["resolution"] for c in r["cases"] for p in c["points"]})
    first = next((abs(p["error"]) for c in r["cases"] for p in c["points"]
                  if p["resolution"] == ns[0] and p["error"]), None) if ns else None
    if first and len(ns) > 1:
        by_n.plot(ns, [first * (ns[0] / n) ** 2 for n in ns], ":", color="0.5", label="∝ h²")
    for ax in (by_n, by_wall):
        if r["tolerance"] is not None:
            ax.axhline(r["tolerance"], ls="--", color="tab:red", lw=0.8,
                       label=f"bound {r['tolerance'] * 100:g} %")
        ax.set_xscale("log")
        ax.set_yscale("log")
        ax.grid(True, which="both", alpha=0.25)
        ax.set_ylabel(f"|relative error| of the {r['quantity']}")
    if ns:
        by_n.set_xticks(ns, [str(n) for n in ns])
        by_n.minorticks_off()
    by_n.set_xlabel(f"N ({r['resolution_meaning']})")
    by_wall.set_xlabel("wall time of the run (s)")
    by_n.legend(fontsize=7)
    _save(fig, r, path)


def _plot_report(r: dict, by_n, by_wall) -> None:
    """The measured value of each case against resolution and wall time."""
    for case in r["cases"]:
        pts = [p for p in case["points"] if math.isfinite(p["measured"])]
        by_n.plot([p["resolution"] for p in pts], [p["measured"] for p in pts], "o-",
                  label=case["label"])
        by_wall.plot([p["wall_s"] for p in pts], [p["measured"] for p in pts], "o-")
    ns = sorted({p["resolution"] for c in r["cases"] for p in c["points"]})
    for ax in (by_n, by_wall):
        ax.set_xscale("log")
        ax.grid(True, which="both", alpha=0.25)
        ax.set_ylabel(r["quantity"])
    if ns:
        by_n.set_xticks(ns, [str(n) for n in ns])
        by_n.minorticks_off()
    by_n.set_xlabel(f"N ({r['resolution_meaning']})")
    by_wall.set_xlabel("wall time of the run (s)")
    by_n.legend(fontsize=7)


def _save(fig, r: dict, path: Path) -> None:
    import matplotlib.pyplot as plt

    from ..util import atomic_write

    material = f" · {r['material']['preset']}" if r["material"] else ""
    fig.suptitle(f"cloth-tui lab {r['test']}{material}", fontsize=10)
    fig.tight_layout()
    with atomic_write(Path(path)) as fh:
        fig.savefig(fh, format="png")
    plt.close(fig)
