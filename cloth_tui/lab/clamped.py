"""The lab's tests of a strip clamped horizontally at one end, bending under its own weight:
`cantilever` (the tip's drop against the heavy elastica at wL³/B = 2, 8, 20) and `peirce`
(ASTM D1388 done virtually: the overhang at which the line from the clamp's edge to the tip
falls 41.5°, and B = w·(O/2)³, which must give back the material's bending rigidity).

The clamp holds the strip's first three columns, its edge halfway between the last two
held ones: the free length is then (N + ½)·h for N free links, and the hinge at the last
held column stands for the half cells on either side of the edge (docs/physics.md,
"Against the elastica"; two held columns at the sheet's border make it 3–11 % too stiff)."""

from __future__ import annotations

import math

import numpy as np

from .elastica import cantilever
from .peirce import PEIRCE_ANGLE, overhang, peirce_rigidity
from .strips import particles_across, strip_scene, timed_frames, warmed_simulation
from .study import Case, Experiment, LabError, Measurement

GRAVITY = 9.81
HELD_COLUMNS = 3
# ASTM D1388's specimen is 25 mm wide. Across the width nothing bends, so a few rows do
# (the cells then longer across than along: the grid's energy allows any aspect).
STRIP_WIDTH = 0.025        # m
MAX_ROWS = 6
CANTILEVER_LOADS = (2.0, 8.0, 20.0)
DEFAULT_MATERIAL = "denim"
PEIRCE_PRESETS = ("denim", "jersey", "tablecloth")
SETTLE_S = 2.0             # s of simulated time for a clamped strip to come to rest
SETTLE_PERIODS = 12.0      # … and at least this many of its first mode's periods
ITERATIONS = 8
SUBSTEPS = 20
PEIRCE_ANGLE_TOLERANCE = math.radians(0.005)  # how near 41.5° the search stops
PEIRCE_MAX_RUNS = 8


def free_length_spacing(free_length: float, links: int) -> float:
    """h with (links + ½)·h = free length: the clamp's edge is half a cell beyond the last
    held column."""
    return free_length / (links + 0.5)


def strip_for_load(load: float, material) -> float:
    """m: the free length L at which the material's strip has wL³/B = load."""
    return math.cbrt(load * material.bending / (material.areal_density * GRAVITY))


def first_mode_period(free_length: float, material) -> float:
    """s: the small-deflection cantilever's first period, 2π/ω₁ with ω₁ = 1.875²·√(B/(ρ_A L⁴))
    (Euler–Bernoulli), the scale on which it settles."""
    omega = 1.8751 ** 2 * math.sqrt(material.bending / (material.areal_density *
                                                        free_length ** 4))
    return 2 * math.pi / omega


def settling_damping(free_length: float, material) -> float:
    """1/s: the material damping rate that settles the first mode in a few periods (about
    half critical); it changes the static answer not at all."""
    return 0.5 * 2 * (2 * math.pi / first_mode_period(free_length, material))


def material_table(material, damping: float) -> dict:
    """The scene's [material] section for `material`, with `damping` (1/s) for settling."""
    return {"areal_density": material.areal_density,
            "stretch": [material.stretch_warp, material.stretch_weft],
            "shear": material.shear, "bending": material.bending, "damping": damping}


def clamped_strip(free_length: float, links: int, material):
    """(scene, rows, columns, h): the strip of `links` free links clamped by its first
    three columns, held where the flat sheet lies."""
    h = free_length_spacing(free_length, links)
    cols = links + HELD_COLUMNS
    length = (cols - 1) * h
    rows = min(MAX_ROWS, particles_across(STRIP_WIDTH, free_length, links))
    scene = strip_scene(size=[length, STRIP_WIDTH], resolution=[cols, rows],
                        pins=[{"cols": [0, HELD_COLUMNS - 1]}],
                        behavior={"solver": "xpbd", "iterations": ITERATIONS,
                                  "substeps": SUBSTEPS},
                        material_section=material_table(
                            material, settling_damping(free_length, material)))
    return scene, rows, cols, h


def settle_clamped(free_length: float, links: int, material) -> dict:
    """Runs the clamped strip to rest; returns its tip's drop and reach from the clamp's
    edge (m, mean over the rows), the line's angle below horizontal and the wall time."""
    scene, rows, cols, h = clamped_strip(free_length, links, material)
    sim = warmed_simulation(scene)
    settle = max(SETTLE_S, SETTLE_PERIODS * first_mode_period(free_length, material))
    wall = timed_frames(sim, math.ceil(settle * scene.behavior.frame_rate))
    x = sim.state.x.reshape(rows, cols, 3)
    edge_x = 0.5 * (x[:, HELD_COLUMNS - 2, 0] + x[:, HELD_COLUMNS - 1, 0])
    drop = float(np.mean(x[:, HELD_COLUMNS - 1, 1] - x[:, -1, 1]))
    reach = float(np.mean(x[:, -1, 0] - edge_x))
    speed = float(np.abs(sim.state.v).max())
    return {"drop": drop, "reach": reach, "chord_angle": math.atan2(drop, reach),
            "wall_s": wall, "max_speed": speed, "max_stretch": sim.stats()["max_stretch"]}


# --- cantilever --------------------------------------------------------------------------------

def _cantilever_material(material):
    from .study import lab_material
    return material if material is not None else lab_material(DEFAULT_MATERIAL)


def _cantilever_cases(material) -> list[Case]:
    m = _cantilever_material(material)
    return [Case(f"wL³/B = {load:g} (L = {strip_for_load(load, m) * 100:.3g} cm of "
                 f"{m.preset or 'the material'})", cantilever(load).tip_drop,
                 {"load": load, "free_length": strip_for_load(load, m)})
            for load in CANTILEVER_LOADS]


def _measure_cantilever(case: Case, links: int, material) -> Measurement:
    m = _cantilever_material(material)
    length = case.params["free_length"]
    r = settle_clamped(length, links, m)
    return Measurement(r["drop"] / length, {"wall_s": r["wall_s"],
                                            "max_stretch": r["max_stretch"]})


CANTILEVER = Experiment(
    name="cantilever",
    summary="a strip clamped horizontally by its first three columns, bending under its own "
            "weight: the tip's drop δ/L against the heavy elastica B·θ'' = −w·(L − s)·cos θ",
    quantity="δ/L", unit="",
    resolution_meaning="free links along the strip (h = L/(N + ½))",
    default_resolutions=(10, 20, 40), min_resolution=4, tolerance=0.02,
    cases=_cantilever_cases, measure=_measure_cantilever,
    setup=f"xpbd with the material, {ITERATIONS} iterations, {SUBSTEPS} substeps, settled "
          f"≥ {SETTLE_S:g} s at half-critical damping (default material {DEFAULT_MATERIAL})")


# --- peirce --------------------------------------------------------------------------------------

def _peirce_materials(material) -> list:
    from .study import lab_material
    return [material] if material is not None else [lab_material(n) for n in PEIRCE_PRESETS]


def _peirce_cases(material) -> list[Case]:
    return [Case(f"{m.preset}: B = {m.bending * 1e6:.4g} µN·m, {m.areal_density * 1e3:g} g/m²",
                 m.bending, {"preset": m.preset,
                             "elastica_overhang": overhang(m.bending, m.areal_density)})
            for m in _peirce_materials(material)]


def peirce_search(chord_at, first_guess: float) -> tuple[float, int]:
    """(overhang, runs): the overhang at which chord_at(O) (rad, growing with O) is 41.5°,
    by the secant method on log O from first_guess and 3 % beyond it."""
    a, b = math.log(first_guess), math.log(1.03 * first_guess)
    fa, fb = chord_at(math.exp(a)) - PEIRCE_ANGLE, chord_at(math.exp(b)) - PEIRCE_ANGLE
    runs = 2
    while abs(fb) > PEIRCE_ANGLE_TOLERANCE:
        if runs >= PEIRCE_MAX_RUNS or fb == fa:
            raise LabError(f"peirce: no overhang found for 41.5° in {runs} runs "
                           f"(last {math.degrees(fb + PEIRCE_ANGLE):.3f}°)")
        a, b, fa = b, b - fb * (b - a) / (fb - fa), fb
        fb = chord_at(math.exp(b)) - PEIRCE_ANGLE
        runs += 1
    return math.exp(b), runs


def _measure_peirce(case: Case, links: int, material) -> Measurement:
    m = next(x for x in _peirce_materials(material) if x.preset == case.params["preset"])
    wall = [0.0]

    def chord_at(length: float) -> float:
        r = settle_clamped(length, links, m)
        wall[0] += r["wall_s"]
        return r["chord_angle"]

    found, runs = peirce_search(chord_at, case.params["elastica_overhang"])
    return Measurement(peirce_rigidity(m.areal_density, found, GRAVITY),
                       {"wall_s": wall[0], "overhang": found, "runs": runs})


PEIRCE = Experiment(
    name="peirce",
    summary="ASTM D1388 done virtually: the overhang O at which the line from the clamp's "
            "edge to the tip falls 41.5°, and B = w·(O/2)³, against the material's B",
    quantity="B", unit="N·m",
    resolution_meaning="free links along the overhang (h = O/(N + ½))",
    default_resolutions=(10, 20, 40), min_resolution=4, tolerance=0.02,
    cases=_peirce_cases, measure=_measure_peirce,
    setup=f"as cantilever; the overhang by the secant method to within "
          f"{math.degrees(PEIRCE_ANGLE_TOLERANCE):g}° of 41.5° (default presets "
          f"{', '.join(PEIRCE_PRESETS)})")
