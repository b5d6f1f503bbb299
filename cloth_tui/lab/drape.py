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

from .strips import strip_scene, timed_frames, warmed_simulation
from .study import Case, Experiment, Measurement

SPECIMEN_RADIUS = 0.15   # m
SUPPORT_RADIUS = 0.09    # m
PRESETS = ("silk", "jersey", "denim", "leather")
SETTLE_S = 3.0
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


def fold_count(xz: np.ndarray) -> int:
    """Folds around the hem: how often its distance from the middle rises through its
    mean, going once around (each fold a crest of the rim's outline)."""
    r = np.hypot(xz[:, 0], xz[:, 1])
    above = r > r.mean()
    return int(np.count_nonzero(above & ~np.roll(above, 1)))


def drape_coefficient(area: float) -> float:
    support = math.pi * SUPPORT_RADIUS ** 2
    return (area - support) / (math.pi * SPECIMEN_RADIUS ** 2 - support)


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
    for SETTLE_S and measures its hem: the drape coefficient, folds and shadow."""
    inside, held, hem, h = disc_masks(n)
    sim = warmed_simulation(scene)
    cut_loose(sim, ~inside)
    wall = timed_frames(sim, math.ceil(SETTLE_S * scene.behavior.frame_rate))
    x = sim.state.x
    centre = x[held].mean(axis=0)
    xz = x[hem_order(n, hem)][:, [0, 2]] - centre[[0, 2]]
    area = shadow_area(xz)
    return {"drape_coefficient": drape_coefficient(area), "folds": fold_count(xz),
            "shadow_cm2": area * 1e4, "wall_s": wall, "state": sim.state}


def _measure(case: Case, n: int, material) -> Measurement:
    from .clamped import material_table

    m = next(x for x in _materials(material) if x.preset == case.params["preset"])
    scene = strip_scene(size=[2 * SPECIMEN_RADIUS] * 2, resolution=[n, n],
                        pins=specimen_pins(n),
                        behavior={"solver": "xpbd", "iterations": ITERATIONS,
                                  "substeps": SUBSTEPS},
                        material_section=material_table(m, SETTLE_DAMPING))
    r = settle_disc(scene, n)
    return Measurement(r["drape_coefficient"], {k: r[k] for k in ("wall_s", "folds",
                                                                  "shadow_cm2")})


def cut_loose(sim, outside: np.ndarray) -> None:
    """Every constraint with a particle in `outside` leaves the solve, as a tear does
    (before the first frame, which starts from the state as it is)."""
    edges = sim.model.edges
    touching = outside[edges[:, 0]] | outside[edges[:, 1]]
    sim.state.alive[touching] = 0
    sim.state.torn += int(np.count_nonzero(touching))


DRAPE = Experiment(
    name="drape",
    summary=f"the Cusick test: a {SPECIMEN_RADIUS * 200:g} cm disc held on an "
            f"{SUPPORT_RADIUS * 200:g} cm support; its drape coefficient and folds (a report)",
    quantity="drape coefficient", unit="",
    resolution_meaning="particles across the disc",
    default_resolutions=(25, 41), min_resolution=11, tolerance=None,
    cases=_cases, measure=_measure,
    setup=f"xpbd with the material, {ITERATIONS} iterations, {SUBSTEPS} substeps, "
          f"{SETTLE_S:g} s settling at damping {SETTLE_DAMPING:g}/s")
