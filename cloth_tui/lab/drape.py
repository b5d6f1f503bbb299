"""The Cusick drape test (BS 5058, ISO 9073-9): a 30 cm disc of fabric held between two
18 cm discs lets its rim fall in folds; the drape coefficient is the share of the annulus
its shadow covers, DC = (S − S_support)/(S_flat − S_support), and the folds are counted
around the rim. A report: there is no analytic value, the lab checks the ranges and the
ordering of the fabrics (a stiffer fabric drapes less, DC nearer 1).

The specimen is a square sheet the disc's diameter across; the particles beyond the disc's
radius are cut loose before the run (every constraint touching one leaves the solve) and
fall away unseen, and the particles within the support's radius are held, as the meter's
two discs clamp them."""

from __future__ import annotations

import math

import numpy as np

from ..sim.tearing import remove_constraints
from .strips import strip_scene, timed_frames, warmed_simulation
from .study import MATERIAL_SOLVERS, Case, Experiment, LabError, Measurement

SPECIMEN_RADIUS = 0.15   # m
SUPPORT_RADIUS = 0.09    # m
PRESETS = ("silk", "jersey", "denim", "leather")
# Settled: the drape coefficient moved less than SETTLED_DC over the last CHECK_S, checked
# from MIN_SETTLE_S on; by MAX_SETTLE_S at the latest (the report's settled time shows it).
MIN_SETTLE_S = 3.0
CHECK_S = 0.5
SETTLED_DC = 1e-3
MAX_SETTLE_S = 10.0
FOLD_DEPTH = 0.02        # a fold's crest stands 2 % of the radius (3 mm) above its troughs
ITERATIONS = 8
SUBSTEPS = 20
SETTLE_DAMPING = 3.0     # 1/s, the material's damping while it settles


def disc_masks(n: int) -> tuple[np.ndarray, np.ndarray, np.ndarray, float]:
    """(inside, held, hem, h) on an n × n grid spanning the specimen's diameter, row-major:
    the particles within the disc, those within the support, the disc's outermost ring
    (within one spacing of its rim) and the spacing."""
    h = 2 * SPECIMEN_RADIUS / (n - 1)
    c = (np.arange(n) - (n - 1) / 2) * h
    zz, xx = np.meshgrid(c, c, indexing="ij")
    r = np.hypot(xx, zz).ravel()
    inside = r <= SPECIMEN_RADIUS + 1e-9
    return inside, r <= SUPPORT_RADIUS + 1e-9, inside & (r > SPECIMEN_RADIUS - h), h


def hem_order(n: int, hem: np.ndarray) -> np.ndarray:
    """The hem's particle indices sorted by their angle on the flat disc."""
    h = 2 * SPECIMEN_RADIUS / (n - 1)
    idx = np.flatnonzero(hem)
    i, j = np.divmod(idx, n)
    angle = np.arctan2((i - (n - 1) / 2) * h, (j - (n - 1) / 2) * h)
    return idx[np.argsort(angle)]


def shadow_area(xz: np.ndarray) -> float:
    """m²: the area inside the hem's projection, a closed polygon in the horizontal plane
    (the shoelace formula); a rim whose folds stand out from the middle never crosses
    itself there, so this is the shadow the meter's lamp casts."""
    x, z = xz[:, 0], xz[:, 1]
    return 0.5 * abs(float(np.dot(x, np.roll(z, -1)) - np.dot(z, np.roll(x, -1))))


def fold_count(kept: np.ndarray, depth: float = FOLD_DEPTH) -> int:
    """Folds around the hem from `kept`, each hem particle's projected distance from the
    middle as a share of its flat one, in order around the rim: the crests that stand at
    least `depth` above the troughs on either side (a zigzag walk once around from the
    lowest point), so the grid's staircase and ripples shallower than that are no folds."""
    start = int(np.argmin(kept))
    walk = np.append(np.roll(kept, -start), kept[start])
    folds, trough, crest = 0, float(walk[0]), None
    for v in walk[1:]:
        if crest is None:
            trough = min(trough, v)
            if v > trough + depth:
                crest = v
        else:
            crest = max(crest, v)
            if v < crest - depth:
                folds += 1
                crest, trough = None, v
    return folds


def drape_coefficient(area: float, flat_area: float) -> float:
    """(S − S_support)/(S_flat − S_support). S_flat is the same hem's shadow before the
    drape: on the grid the hem's polygon falls short of the disc's π·R² (by 10 % at 25
    particles across), and a specimen that did not drape must read 1 at every grid."""
    support = math.pi * SUPPORT_RADIUS ** 2
    return (area - support) / (flat_area - support)


def _materials(material) -> list:
    from .study import lab_material
    return [material] if material is not None else [lab_material(n) for n in PRESETS]


def _cases(material) -> list[Case]:
    from ..materials.schema import bending_length
    return [Case(f"{m.preset}: bending length {bending_length(m) * 100:.3g} cm", None,
                 {"preset": m.preset}) for m in _materials(material)]


def specimen_pins(n: int) -> list[dict]:
    """The support's pin group on an n × n grid: every particle within its radius, held."""
    _, held, _, _ = disc_masks(n)
    return [{"at": [[int(i), int(j)] for i, j in zip(*np.divmod(np.flatnonzero(held), n))]}]


def settle_disc(scene, n: int) -> dict:
    """Cuts the disc out of `scene`'s n × n sheet (pinned by specimen_pins), lets it settle
    (the drape coefficient still to SETTLED_DC over CHECK_S) and measures its hem: the
    drape coefficient, folds and shadow."""
    inside, held, hem, h = disc_masks(n)
    order = hem_order(n, hem)
    sim = warmed_simulation(scene)
    flat = _hem_xz(sim.state.x, held, order)
    flat_area = shadow_area(flat)
    flat_radius = np.hypot(flat[:, 0], flat[:, 1])
    cut_loose(sim, ~inside)
    rate = scene.behavior.frame_rate
    wall = timed_frames(sim, math.ceil(MIN_SETTLE_S * rate))
    dc = drape_coefficient(shadow_area(_hem_xz(sim.state.x, held, order)), flat_area)
    while True:
        wall += timed_frames(sim, math.ceil(CHECK_S * rate))
        last, xz = dc, _hem_xz(sim.state.x, held, order)
        dc = drape_coefficient(shadow_area(xz), flat_area)
        if not np.isfinite(xz).all():
            raise LabError(f"the drape diverged at {n} particles across")
        if abs(dc - last) < SETTLED_DC or sim.state.t >= MAX_SETTLE_S:
            break
    kept = np.hypot(xz[:, 0], xz[:, 1]) / flat_radius
    return {"drape_coefficient": dc, "folds": fold_count(kept),
            "shadow_cm2": shadow_area(xz) * 1e4, "settled_s": sim.state.t,
            "still_moving": abs(dc - last), "wall_s": wall, "state": sim.state}


def _hem_xz(x: np.ndarray, held: np.ndarray, order: np.ndarray) -> np.ndarray:
    """The hem's horizontal positions from the support's middle, in order around it."""
    return x[order][:, [0, 2]] - x[held].mean(axis=0)[[0, 2]]


def _measure(case: Case, n: int, material, solver: str) -> Measurement:
    from .clamped import material_table

    m = next(x for x in _materials(material) if x.preset == case.params["preset"])
    scene = strip_scene(size=[2 * SPECIMEN_RADIUS] * 2, resolution=[n, n],
                        pins=specimen_pins(n),
                        behavior={"solver": solver, "iterations": ITERATIONS,
                                  "substeps": SUBSTEPS},
                        material_section=material_table(m, SETTLE_DAMPING))
    r = settle_disc(scene, n)
    return Measurement(r["drape_coefficient"], {k: r[k] for k in ("wall_s", "folds",
                                                                  "shadow_cm2", "settled_s")})


def cut_loose(sim, outside: np.ndarray) -> None:
    """Every constraint with a particle in `outside` leaves the solve, as a tear does
    (before the first frame, which starts from the state as it is)."""
    edges = sim.model.edges
    touching = outside[edges[:, 0]] | outside[edges[:, 1]]
    remove_constraints(sim.state, touching)


DRAPE = Experiment(
    name="drape",
    summary=f"the Cusick test: a {SPECIMEN_RADIUS * 200:g} cm disc held on an "
            f"{SUPPORT_RADIUS * 200:g} cm support; its drape coefficient and folds (a report)",
    quantity="drape coefficient", unit="",
    resolution_meaning="particles across the disc",
    default_resolutions=(25, 41), min_resolution=11, tolerance=None,
    cases=_cases, measure=_measure, solvers=MATERIAL_SOLVERS,
    setup=f"{{solver}} with the material, {ITERATIONS} iterations, {SUBSTEPS} substeps, "
          f"damping {SETTLE_DAMPING:g}/s, settled until the coefficient moves < "
          f"{SETTLED_DC:g} per {CHECK_S:g} s (≥ {MIN_SETTLE_S:g} s); folds at least "
          f"{FOLD_DEPTH * 100:g} % of the radius deep")
