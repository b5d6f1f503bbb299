"""What every lab test shares: its description (`Experiment`), a run over resolutions that
collects measured against expected, the error, the wall time and the fitted convergence
order, and the material the user named. Plain data in, plain dicts out (cli.py prints,
writes JSON and plots them)."""

from __future__ import annotations

import math
import time
from dataclasses import dataclass, field
from typing import Callable

from ..sim.solvers import registry as solver_registry

MAX_RESOLUTION = 256  # segments along a strip (particles across a disc): minutes beyond
# What a test of a material may run it with (--solver): every solver that takes one, the
# reference first (the lab's default: its results are stated for it).
MATERIAL_SOLVERS = solver_registry.Names(takes_material=True, reference_first=True)


class LabError(ValueError):
    """Bad input to the lab (a test, material or resolution it cannot run): one line."""


@dataclass(frozen=True)
class Case:
    """One configuration of a test (a load, a preset), with its computed expectation."""
    label: str
    expected: float | None     # None: the test reports, there is no analytic value
    params: dict = field(default_factory=dict)


@dataclass(frozen=True)
class Measurement:
    value: float
    extra: dict = field(default_factory=dict)  # what else the run saw (stretch, settling…)


@dataclass(frozen=True)
class Experiment:
    name: str
    summary: str                  # one line: what is measured against what
    quantity: str                 # what `value` is, e.g. "sag"
    unit: str
    resolution_meaning: str       # what a resolution N is in this test
    default_resolutions: tuple[int, ...]
    min_resolution: int
    tolerance: float | None       # the relative error the lab's bound allows (None: a report)
    cases: Callable               # (material | None) -> list[Case]
    measure: Callable             # (case, resolution, material | None, solver) -> Measurement
    setup: str = ""               # the solver settings, said in the report ({solver} filled in)
    solvers: tuple[str, ...] = ()  # the solvers it can run (the first its own); () if fixed
    plot: Callable | None = None  # (result, path): its own --plot; None: the convergence plot


def parse_resolutions(text: str, experiment: Experiment) -> list[int]:
    """'8,16,32' → [8, 16, 32], each an integer in the test's range, no repeats."""
    out = []
    for part in text.split(","):
        part = part.strip()
        try:
            n = int(part)
        except ValueError:
            raise LabError(f"--resolutions: {part!r} is not an integer (give N,N,…, e.g. "
                           f"{','.join(map(str, experiment.default_resolutions))})") from None
        if not experiment.min_resolution <= n <= MAX_RESOLUTION:
            raise LabError(f"--resolutions: {n} is outside {experiment.min_resolution}–"
                           f"{MAX_RESOLUTION} for {experiment.name} "
                           f"({experiment.resolution_meaning})")
        if n in out:
            raise LabError(f"--resolutions: {n} is given twice")
        out.append(n)
    return sorted(out)


def fitted_order(points: list[dict]) -> float | None:
    """The slope of log |error| against log h (h = 1/resolution), least squares: p in
    error ∝ hᵖ. None with fewer than two points that have an error."""
    pts = [(math.log(1 / p["resolution"]), math.log(abs(p["error"]))) for p in points
           if p.get("error") not in (None, 0.0) and math.isfinite(p["error"])]
    if len(pts) < 2:
        return None
    mx = sum(x for x, _ in pts) / len(pts)
    my = sum(y for _, y in pts) / len(pts)
    sxx = sum((x - mx) ** 2 for x, _ in pts)
    return sum((x - mx) * (y - my) for x, y in pts) / sxx


def check_solver(experiment: Experiment, solver: str | None) -> str | None:
    """The solver the test runs (its first by default); a LabError for one it cannot."""
    if solver is None:
        return experiment.solvers[0] if experiment.solvers else None
    if not experiment.solvers:
        raise LabError(f"--solver: {experiment.name} runs its own solver ({experiment.setup})"
                       f"; --solver is for the tests of a material")
    if solver not in experiment.solvers:
        raise LabError(f"--solver: {solver!r} cannot run {experiment.name}; "
                       f"choose {' or '.join(experiment.solvers)}")
    return solver


def run(experiment: Experiment, resolutions: list[int], material=None,
        progress: Callable[[int, int, str], None] | None = None,
        solver: str | None = None) -> dict:
    """Every case at every resolution, with `solver` (check_solver). `progress(done, total,
    what)` before each run."""
    solver = check_solver(experiment, solver)
    started = time.perf_counter()
    cases = experiment.cases(material)
    total, done = len(cases) * len(resolutions), 0
    out_cases = []
    for case in cases:
        points = []
        for n in resolutions:
            if progress:
                progress(done, total, f"{case.label}, N = {n}")
            t0 = time.perf_counter()
            m = experiment.measure(case, n, material, solver)
            wall = m.extra.pop("wall_s", time.perf_counter() - t0)
            error = (m.value / case.expected - 1) if case.expected else None
            points.append({"resolution": n, "measured": m.value, "error": error,
                           "wall_s": wall, **m.extra})
            done += 1
        out_cases.append({"label": case.label, "expected": case.expected,
                          "params": case.params, "points": points,
                          "order": fitted_order(points)})
    if progress:
        progress(done, total, "done")
    return {"test": experiment.name, "summary": experiment.summary,
            "quantity": experiment.quantity, "unit": experiment.unit,
            "resolution_meaning": experiment.resolution_meaning,
            "setup": experiment.setup.replace("{solver}", solver or ""),
            "solver": solver, "tolerance": experiment.tolerance,
            "material": material_summary(material), "cases": out_cases,
            "elapsed_s": time.perf_counter() - started}


def material_summary(material) -> dict | None:
    if material is None:
        return None
    return {"preset": material.preset, "areal_density": material.areal_density,
            "stretch": [material.stretch_warp, material.stretch_weft],
            "shear": material.shear, "bending": material.bending}


def lab_material(name: str | None):
    """The preset `name` as a Material, or None; a name not in the table is a LabError
    listing the presets."""
    if name is None:
        return None
    from ..materials.errors import MaterialError
    from ..materials.schema import material_from_table
    try:
        return material_from_table({"preset": name}, "--material")
    except MaterialError as e:
        raise LabError(str(e).replace("--material.preset", "--material")) from None
