"""The accuracy study's physical reference: the lab's clamped strip of denim at wL³/B = 8
(the Peirce test's load), its tip drop against the heavy elastica's, by resolution and wall
time, for every solver that can simulate a material. A solver that cannot (its constraints
take no material's compliance, so no bending rigidity in N·m) is listed with the scene's
reason, not run; one whose strip does not settle at a resolution is listed with the lab's
words for it."""

from __future__ import annotations

from ..lab import clamped
from ..lab.elastica import cantilever
from ..lab.study import LabError, lab_material
from ..scene import SOLVERS, SceneError

LOAD = 8.0
PRESET = "denim"


def solver_problem(solver: str) -> str | None:
    """Why `solver` cannot run the clamped strip's material, or None."""
    m = lab_material(PRESET)
    try:
        clamped.clamped_strip(clamped.strip_for_load(LOAD, m), 4, m, solver)
    except SceneError as e:
        return str(e).split(";")[0]  # the reason, not the advice on other keys
    return None


def cantilever_point(solver: str, links: int) -> dict:
    """One settled strip: δ/L against the elastica's, the frames' wall time, substeps."""
    m = lab_material(PRESET)
    length = clamped.strip_for_load(LOAD, m)
    try:
        r = clamped.settle_clamped(length, links, m, solver)
    except LabError as e:  # it did not settle: said, not measured
        return {"solver": solver, "links": links, "unsettled": str(e)}
    expected = cantilever(LOAD).tip_drop
    return {"solver": solver, "links": links, "tip_drop": r["drop"] / length,
            "error": r["drop"] / length / expected - 1, "wall_s": r["wall_s"],
            "substeps": r["substeps"], "iterations": clamped.ITERATIONS}


def physical_calls(links: tuple) -> list[tuple]:
    return [(cantilever_point, (s, n)) for s in SOLVERS if solver_problem(s) is None
            for n in links]


def physical_study(links: tuple, results: list) -> dict:
    """The reference's table from the results of physical_calls(links), in order."""
    m = lab_material(PRESET)
    return {"load": LOAD, "preset": PRESET, "expected": cantilever(LOAD).tip_drop,
            "free_length": clamped.strip_for_load(LOAD, m), "links": list(links),
            "points": [r for r in results if "unsettled" not in r],
            "unsettled": [r for r in results if "unsettled" in r],
            "not_run": {s: why for s in SOLVERS if (why := solver_problem(s)) is not None}}


def format_physical(p: dict) -> list[str]:
    out = [f"Physical reference: a {p['preset']} strip clamped horizontally, "
           f"{p['free_length'] * 100:.3g} cm free (wL³/B = {p['load']:g}); tip drop δ/L "
           f"against the heavy elastica's {p['expected']:.4f}:",
           f"{'solver':<10}{'N':>5}{'δ/L':>10}{'error':>10}{'substeps':>10}{'wall (s)':>10}"]
    for q in p["points"]:
        out.append(f"{q['solver']:<10}{q['links']:>5}{q['tip_drop']:>10.4f}"
                   f"{q['error']:>+10.2%}{q['substeps']:>10}{q['wall_s']:>10.2f}")
    for q in p.get("unsettled", []):
        out.append(f"{q['solver']:<10}{q['links']:>5} did not settle: {q['unsettled']}")
    for solver, why in p["not_run"].items():
        out.append(f"{solver:<10} not run: {why}")
    return out
