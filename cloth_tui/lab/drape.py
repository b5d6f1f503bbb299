"""The Cusick drape test (BS 5058, ISO 9073-9): a 30 cm disc of fabric held between two
18 cm discs lets its rim fall in folds; the drape coefficient is the share of the annulus
its shadow covers, DC = (S − S_support)/(S_flat − S_support), and the folds are counted
around the rim. A report: there is no analytic value, the lab checks the ranges and the
ordering of the fabrics (a stiffer fabric drapes less, DC nearer 1).

The specimen is a square sheet the disc's diameter across. The triangles whose area makes
the disc's (drape_shadow.specimen_triangles) are kept. Every other particle is cut loose
before the run (every constraint touching one leaves the solve) and falls away unseen. The
particles within the support's radius are held, as the meter's two discs clamp them. The
coefficient is read from the shadow of the kept triangles (drape_shadow.shadow_area)."""

from __future__ import annotations

import math

import numpy as np

from ..sim.effects.tearing import remove_constraints
from .drape_shadow import (boundary_particles, grid_coords, shadow_area,
                           specimen_triangles)
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
IMPERFECTION = 5e-3     # m: the flat specimen's largest departure from flat, at the rim
IMPERFECTION_SEED = 5058
REACH = 1.1 * SPECIMEN_RADIUS  # m: the raster's half side, past the specimen's widest corner
ITERATIONS = 8
SUBSTEPS = 20
SETTLE_DAMPING = 3.0     # 1/s, the material's damping while it settles


def disc_masks(n: int) -> tuple[np.ndarray, np.ndarray, np.ndarray, float]:
    """(inside, held, hem, h) on an n × n grid spanning the specimen's diameter, row-major:
    the particles of the specimen's triangles (drape_shadow.specimen_triangles), those
    within the support, the specimen's outline and the spacing."""
    xz, h = grid_coords(n, SPECIMEN_RADIUS)
    tri, _ = specimen_triangles(n, SPECIMEN_RADIUS)
    inside = np.zeros(n * n, dtype=bool)
    inside[tri.ravel()] = True
    hem = np.zeros(n * n, dtype=bool)
    hem[boundary_particles(tri)] = True
    return inside, np.hypot(xz[:, 0], xz[:, 1]) <= SUPPORT_RADIUS + 1e-9, hem, h


def hem_order(n: int, hem: np.ndarray) -> np.ndarray:
    """The hem's particle indices sorted by their angle on the flat disc."""
    xz, _ = grid_coords(n, SPECIMEN_RADIUS)
    idx = np.flatnonzero(hem)
    return idx[np.argsort(np.arctan2(xz[idx, 1], xz[idx, 0]))]


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


def drape_coefficient(area: float, flat_area: float, support_area: float) -> float:
    """(S − S_support)/(S_flat − S_support), each area counted on the same raster (a
    specimen that did not drape reads 1, a shadow no wider than the support 0)."""
    return (area - support_area) / (flat_area - support_area)


def imperfection(xz: np.ndarray) -> np.ndarray:
    """m: the specimen's departure from flat, up or down, at the flat positions `xz`: zero
    on the support, growing as the square of the distance from it to at most IMPERFECTION
    at the rim (and no more beyond, where a corner of the staircase stands out), around the
    rim a fixed mix of the modes 2 to 12 with seeded phases. A fabric is never flat;
    without this the fall's symmetry is broken by the grid's own pattern, a different one
    at every resolution, and the folds (and the coefficient with them) follow it. The same
    function of the flat disc at every resolution lets the mechanics choose the folds
    alike on every grid."""
    rng = np.random.default_rng(IMPERFECTION_SEED)
    modes = np.arange(2, 13)
    phases = rng.uniform(0, 2 * np.pi, len(modes))
    theta = np.arctan2(xz[:, 1], xz[:, 0])
    around = np.cos(np.outer(theta, modes) + phases).sum(axis=1)
    t = np.linspace(0, 2 * np.pi, 4096, endpoint=False)
    around /= np.abs(np.cos(np.outer(t, modes) + phases).sum(axis=1)).max()
    s = np.clip((np.hypot(xz[:, 0], xz[:, 1]) - SUPPORT_RADIUS)
                / (SPECIMEN_RADIUS - SUPPORT_RADIUS), 0.0, 1.0)
    return IMPERFECTION * s * s * around


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
    """Cuts the disc out of `scene`'s n × n sheet (pinned by specimen_pins), lifts it by
    the imperfection, lets it settle (the drape coefficient still to SETTLED_DC over
    CHECK_S) and measures its shadow: the drape coefficient, the folds of its hem, and the
    projected specimen (`xz`, `triangles`) for a picture."""
    inside, held, hem, h = disc_masks(n)
    tri, _ = specimen_triangles(n, SPECIMEN_RADIUS)
    order = hem_order(n, hem)
    sim = warmed_simulation(scene)
    flat = _plan(sim.state.x, held)
    flat_radius = np.hypot(flat[order, 0], flat[order, 1])
    support = shadow_area(flat[:0], tri[:0], SUPPORT_RADIUS, REACH)
    flat_area = shadow_area(flat, tri, SUPPORT_RADIUS, REACH)
    cut_loose(sim, ~inside)
    lift = imperfection(flat)
    for x in (sim.state.x, sim.state.x_prev):
        x[:, 1] += lift

    def coefficient() -> tuple[float, np.ndarray]:
        xz = _plan(sim.state.x, held)
        if not np.isfinite(xz[inside]).all():
            raise LabError(f"the drape diverged at {n} particles across")
        return drape_coefficient(shadow_area(xz, tri, SUPPORT_RADIUS, REACH), flat_area,
                                 support), xz

    rate = scene.behavior.frame_rate
    wall = timed_frames(sim, math.ceil(MIN_SETTLE_S * rate))
    dc, xz = coefficient()
    while True:
        wall += timed_frames(sim, math.ceil(CHECK_S * rate))
        last = dc
        dc, xz = coefficient()
        if abs(dc - last) < SETTLED_DC or sim.state.t >= MAX_SETTLE_S:
            break
    kept = np.hypot(xz[order, 0], xz[order, 1]) / flat_radius
    return {"drape_coefficient": dc, "folds": fold_count(kept),
            "shadow_cm2": shadow_area(xz, tri, SUPPORT_RADIUS, REACH) * 1e4,
            "settled_s": sim.state.t, "still_moving": abs(dc - last), "wall_s": wall,
            "state": sim.state, "xz": xz, "triangles": tri, "flat_area_cm2": flat_area * 1e4}


def _plan(x: np.ndarray, held: np.ndarray) -> np.ndarray:
    """Every particle's horizontal position from the support's middle."""
    return x[:, [0, 2]] - x[held].mean(axis=0)[[0, 2]]


def _measure(case: Case, n: int, material, solver: str) -> Measurement:
    from .clamped import material_table

    m = next(x for x in _materials(material) if x.preset == case.params["preset"])
    scene = strip_scene(size=[2 * SPECIMEN_RADIUS] * 2, resolution=[n, n],
                        pins=specimen_pins(n),
                        behavior={"solver": solver, "iterations": ITERATIONS,
                                  "substeps": SUBSTEPS},
                        material_section=material_table(m, SETTLE_DAMPING))
    r = settle_disc(scene, n)
    outline = r["xz"][hem_order(n, disc_masks(n)[2])]
    return Measurement(r["drape_coefficient"],
                       {k: r[k] for k in ("wall_s", "folds", "shadow_cm2", "settled_s")}
                       | {"outline": np.round(outline, 5).tolist()})


def _plot(result: dict, path) -> None:
    """--plot: the shadows from above beside the coefficient (drape_plot)."""
    from .drape_plot import plot_drape
    plot_drape(result, path)


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
    cases=_cases, measure=_measure, solvers=MATERIAL_SOLVERS, plot=_plot,
    setup=f"{{solver}} with the material, {ITERATIONS} iterations, {SUBSTEPS} substeps, "
          f"damping {SETTLE_DAMPING:g}/s, settled until the coefficient moves < "
          f"{SETTLED_DC:g} per {CHECK_S:g} s (≥ {MIN_SETTLE_S:g} s); folds at least "
          f"{FOLD_DEPTH * 100:g} % of the radius deep")
