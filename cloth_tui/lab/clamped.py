"""The lab's tests of a strip clamped horizontally at one end, bending under its own weight:
`cantilever` (the tip's drop against the heavy elastica at wL³/B = 2, 8, 20) and `peirce`
(ASTM D1388 done virtually: the overhang at which the line from the clamp's edge to the tip
falls 41.5°, and B = w·(O/2)³, which must give back the material's bending rigidity).

A strip along the grid's x is cut along the warp, one along z along the weft, and each bends
with its own B (materials.schema.strip_rigidities); the Peirce test cuts both where the fabric
bends by direction.

The clamp holds the strip's first three columns, its edge halfway between the last two
held ones: the free length is then (N + ½)·h for N free links, and the hinge at the last
held column stands for the half cells on either side of the edge (docs/physics.md,
"Against the elastica"; two held columns at the sheet's border make it 3–11 % too stiff)."""

from __future__ import annotations

import math

import numpy as np

from ..sim.solvers import registry as solver_registry
from .elastica import cantilever
from .peirce import PEIRCE_ANGLE, overhang, peirce_rigidity
from .strips import particles_across, strip_scene, timed_frames, warmed_simulation
from .study import MATERIAL_SOLVERS, Case, Experiment, LabError, Measurement

GRAVITY = 9.81
HELD_COLUMNS = 3
# ASTM D1388's specimen is 25 mm wide. Across the width nothing bends, so a few rows do
# (the cells then longer across than along: the grid's energy allows any aspect).
STRIP_WIDTH = 0.025        # m
MAX_ROWS = 6
CANTILEVER_LOADS = (2.0, 8.0, 20.0)
DEFAULT_MATERIAL = "denim"
PEIRCE_PRESETS = ("denim", "jersey", "tablecloth")
# Settled: the tip's drop moved by less than SETTLED_DRIFT·L over each of the last
# STILL_CHECKS checks, checked every CHECK_PERIODS of the first mode from MIN_PERIODS on, and
# no particle is faster than would move it that far in a check; not by MAX_PERIODS: a
# LabError. The tip alone passes by chance on a strip that never comes to rest: lbfgs at the
# lab's iterations jitters by ~1e-3·L, and at 10 links its tip once read still at three
# checks in a row while its fastest particle moved at 1.3 mm/s, 550× that speed (a strip at
# rest: 1e-8 m/s, a hundredth of it).
SETTLED_DRIFT = 1e-5
STILL_CHECKS = 3
CHECK_PERIODS = 0.5
MIN_PERIODS = 3.0
MAX_PERIODS = 40.0
ITERATIONS = 8
FRAME_RATE = 60.0
SUBSTEPS = 20              # the fewest per frame
# The most bending per substep, h²·B/(ρ_A·dx⁴), the warm-started stencils are given: beyond
# ~2 at 8 iterations the unconverged stretch and the carried bending stop settling
# (docs/physics.md, "Warm-started bending").
MAX_BENDING_PER_STEP = 1.0
PEIRCE_ANGLE_TOLERANCE = math.radians(0.005)  # how near 41.5° the search stops
PEIRCE_MAX_RUNS = 8


def free_length_spacing(free_length: float, links: int) -> float:
    """h with (links + ½)·h = free length: the clamp's edge is half a cell beyond the last
    held column."""
    return free_length / (links + 0.5)


DIRECTIONS = ("warp", "weft")  # a strip cut along x, or along z


def strip_bending(material, along: str = "warp") -> float:
    """N·m: the rigidity a strip cut along `along` bends with."""
    from ..materials.schema import strip_rigidities
    return strip_rigidities(material)[DIRECTIONS.index(along)]


def strip_for_load(load: float, material, along: str = "warp") -> float:
    """m: the free length L at which the material's strip has wL³/B = load."""
    return math.cbrt(load * strip_bending(material, along) /
                     (material.areal_density * GRAVITY))


def first_mode_period(free_length: float, material, along: str = "warp") -> float:
    """s: the small-deflection cantilever's first period, 2π/ω₁ with ω₁ = 1.875²·√(B/(ρ_A L⁴))
    (Euler–Bernoulli), the scale on which it settles."""
    omega = 1.8751 ** 2 * math.sqrt(strip_bending(material, along) / (material.areal_density *
                                                        free_length ** 4))
    return 2 * math.pi / omega


def settling_damping(free_length: float, material, along: str = "warp") -> float:
    """1/s: the material damping rate that settles the first mode in a few periods (about
    half critical); it changes the static answer not at all."""
    return 0.5 * 2 * (2 * math.pi / first_mode_period(free_length, material, along))


def material_table(material, damping: float) -> dict:
    """The scene's [material] section for `material`, with `damping` (1/s) for settling.
    Its bending by direction is written as the [warp, weft] strips' rigidities: a strip
    along x or z bends as the material does, while a preset's measured 45° fold becomes
    the pair's (twist stencils of √(B_warp·B_weft)) and its stretch is linear."""
    from ..materials.schema import strip_rigidities
    warp, weft = strip_rigidities(material)
    return {"areal_density": material.areal_density,
            "stretch": [material.stretch_warp, material.stretch_weft],
            "shear": material.shear,
            "bending": material.bending if material.bending_by_direction is None
            else [warp, weft], "damping": damping}


def substeps_for(spacing: float, material, frame_rate: float, along: str = "warp") -> int:
    """Substeps per frame that keep h²·B/(ρ_A·dx⁴) within MAX_BENDING_PER_STEP (at least
    SUBSTEPS): the bending's stiffness per step grows as 1/dx⁴, so a finer strip needs
    shorter steps, h ∝ dx²."""
    longest = spacing ** 2 * math.sqrt(MAX_BENDING_PER_STEP * material.areal_density /
                                       strip_bending(material, along))
    return max(SUBSTEPS, math.ceil(1.0 / (frame_rate * longest)))


def clamped_strip(free_length: float, links: int, material, solver: str | None = None,
                  along: str = "warp", behavior: dict | None = None):
    """(scene, across, lengthwise, h): the strip of `links` free links (`lengthwise`
    particles, `across` of them side by side) clamped by its first three, held where the
    flat sheet lies, cut along the warp (x) or the weft (z), solved by `solver` (the
    reference solver if None) at the lab's substeps and iterations, or with `behavior`'s
    keys over them; a SceneError if it cannot simulate the material."""
    solver = solver or solver_registry.reference()
    h = free_length_spacing(free_length, links)
    lengthwise = links + HELD_COLUMNS
    length = (lengthwise - 1) * h
    across = min(MAX_ROWS, particles_across(STRIP_WIDTH, free_length, links))
    held = [0, HELD_COLUMNS - 1]
    if along == "warp":
        size, resolution, pin = [length, STRIP_WIDTH], [lengthwise, across], {"cols": held}
    else:
        size, resolution, pin = [STRIP_WIDTH, length], [across, lengthwise], {"rows": held}
    lab = {"solver": solver, "iterations": ITERATIONS, "frame_rate": FRAME_RATE,
           "substeps": substeps_for(h, material, FRAME_RATE, along)}
    scene = strip_scene(size=size, resolution=resolution, pins=[pin],
                        behavior=lab | (behavior or {}),
                        material_section=material_table(
                            material, settling_damping(free_length, material, along)))
    return scene, across, lengthwise, h


def _tip(sim, across: int, lengthwise: int, along: str) -> tuple[float, float]:
    """(drop, reach) of the tip from the clamp's edge, m, mean across the strip."""
    if along == "warp":   # rows of particles along x
        x, axis = sim.state.x.reshape(across, lengthwise, 3), 0
    else:                 # along z: the grid's rows are the strip's length
        x, axis = sim.state.x.reshape(lengthwise, across, 3).transpose(1, 0, 2), 2
    edge = 0.5 * (x[:, HELD_COLUMNS - 2, axis] + x[:, HELD_COLUMNS - 1, axis])
    return (float(np.mean(x[:, HELD_COLUMNS - 1, 1] - x[:, -1, 1])),
            float(np.mean(x[:, -1, axis] - edge)))


def settle_clamped(free_length: float, links: int, material, solver: str | None = None,
                   along: str = "warp", behavior: dict | None = None) -> dict:
    """Runs the clamped strip (cut along the warp or the weft) to rest (its tip still to
    SETTLED_DRIFT·L over each of STILL_CHECKS half periods in a row, and no particle fast
    enough to move that far in one); returns its tip's drop
    and reach from the clamp's edge (m, mean across the strip), the line's angle below
    horizontal, the wall time and the solve's settings (`behavior`: clamped_strip's)."""
    scene, across, lengthwise, h = clamped_strip(free_length, links, material, solver, along,
                                                 behavior)
    sim = warmed_simulation(scene)
    period = first_mode_period(free_length, material, along)
    chunk = max(1, math.ceil(CHECK_PERIODS * period * scene.behavior.frame_rate))
    wall = timed_frames(sim, math.ceil(MIN_PERIODS * period * scene.behavior.frame_rate))
    drop, reach = _tip(sim, across, lengthwise, along)
    still = 0
    while True:
        wall += timed_frames(sim, chunk)
        last = drop
        drop, reach = _tip(sim, across, lengthwise, along)
        if not math.isfinite(drop) or not sim.stats().finite:
            raise LabError(f"the clamped strip diverged at {links} links "
                           f"({scene.behavior.substeps} substeps)")
        speed = float(np.sqrt(np.einsum("ij,ij->i", sim.state.v, sim.state.v)).max())
        quiet = (abs(drop - last) < SETTLED_DRIFT * free_length
                 and speed * CHECK_PERIODS * period < SETTLED_DRIFT * free_length)
        still = still + 1 if quiet else 0
        if still == STILL_CHECKS:
            break
        if sim.state.t > MAX_PERIODS * period:
            raise LabError(f"the clamped strip did not settle in {MAX_PERIODS:g} periods at "
                           f"{links} links (its tip still moving "
                           f"{abs(drop - last) / free_length:.1e}·L per check, its fastest "
                           f"particle at {speed:.1e} m/s)")
    return {"drop": drop, "reach": reach, "chord_angle": math.atan2(drop, reach),
            "wall_s": wall, "max_speed": float(np.abs(sim.state.v).max()),
            "max_stretch": sim.stats().max_stretch, "substeps": scene.behavior.substeps,
            "settled_s": sim.state.t}


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


def _measure_cantilever(case: Case, links: int, material, solver: str) -> Measurement:
    m = _cantilever_material(material)
    length = case.params["free_length"]
    r = settle_clamped(length, links, m, solver)
    return Measurement(r["drop"] / length, {k: r[k] for k in ("wall_s", "max_stretch",
                                                              "substeps")})


CANTILEVER = Experiment(
    name="cantilever",
    summary="a strip clamped horizontally by its first three columns, bending under its own "
            "weight: the tip's drop δ/L against the heavy elastica B·θ'' = −w·(L − s)·cos θ",
    quantity="δ/L", unit="",
    resolution_meaning="free links along the strip (h = L/(N + ½))",
    default_resolutions=(10, 20, 40), min_resolution=4, tolerance=0.02,
    cases=_cantilever_cases, measure=_measure_cantilever, solvers=MATERIAL_SOLVERS,
    setup=f"{{solver}} with the material, {ITERATIONS} iterations, substeps keeping "
          f"h²·B/(ρ_A·dx⁴) ≤ {MAX_BENDING_PER_STEP:g} (at least {SUBSTEPS}), settled at "
          f"half-critical damping until the tip moves < {SETTLED_DRIFT:g}·L per half period "
          f"{STILL_CHECKS} times in a row, no particle faster (default material "
          f"{DEFAULT_MATERIAL})")


# --- peirce --------------------------------------------------------------------------------------

def _peirce_materials(material) -> list:
    from .study import lab_material
    return [material] if material is not None else [lab_material(n) for n in PEIRCE_PRESETS]


def _peirce_cases(material) -> list[Case]:
    """A strip cut along the warp; and along the weft where the fabric bends by direction."""
    cases = []
    for m in _peirce_materials(material):
        directions = DIRECTIONS if m.bending_by_direction is not None else ("",)
        for direction in directions:
            b = strip_bending(m, direction or "warp")
            name = " ".join(filter(None, (m.preset, direction))) or "the material"
            cases.append(Case(f"{name}: B = {b * 1e6:.4g} µN·m, {m.areal_density * 1e3:g} g/m²",
                              b, {"preset": m.preset, "direction": direction or "warp",
                                  "elastica_overhang": overhang(b, m.areal_density)}))
    return cases


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


def _measure_peirce(case: Case, links: int, material, solver: str) -> Measurement:
    m = next(x for x in _peirce_materials(material) if x.preset == case.params["preset"])
    wall = [0.0]

    def chord_at(length: float) -> float:
        r = settle_clamped(length, links, m, solver, case.params["direction"])
        wall[0] += r["wall_s"]
        return r["chord_angle"]

    found, runs = peirce_search(chord_at, case.params["elastica_overhang"])
    return Measurement(peirce_rigidity(m.areal_density, found, GRAVITY),
                       {"wall_s": wall[0], "overhang": found, "runs": runs})


PEIRCE = Experiment(
    name="peirce",
    summary="ASTM D1388 done virtually: the overhang O at which the line from the clamp's "
            "edge to the tip falls 41.5°, and B = w·(O/2)³, against the material's B (of "
            "the strip cut along the warp, and along the weft where it bends by direction)",
    quantity="B", unit="N·m",
    resolution_meaning="free links along the overhang (h = O/(N + ½))",
    default_resolutions=(10, 20, 40), min_resolution=4, tolerance=0.02,
    cases=_peirce_cases, measure=_measure_peirce, solvers=MATERIAL_SOLVERS,
    setup=f"{{solver}} as in cantilever; the overhang by the secant method to within "
          f"{math.degrees(PEIRCE_ANGLE_TOLERANCE):g}° of 41.5° (default presets "
          f"{', '.join(PEIRCE_PRESETS)})")
