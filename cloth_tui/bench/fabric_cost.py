"""The cost of a fabric's accuracy: what each solver that takes a material spends to meet the
default accuracy on a measured fabric as the sheet grows.

The sheet: 1 m of denim (the measured 11 oz denim, a stiff woven: the hardest case for a
solver of its stretch) held by two clips at the corners of its top edge, each 1/16 of the
edge long, 1 m above nothing, falling from flat. Every setting is the default (adaptive
substeps, the default error tolerance, the fabric's own damping; the default scene's solver at
that scene's substeps and iterations). `n` is the number of cells
a side, a multiple of 16 so every grid's clips hold the same length of edge; the sheet has
(n + 1)² particles. Reported per solver and size as for the original scene
(accuracy_cost.py): substeps and passes used, whether the tolerance was met, ms per frame
(median, fastest and slowest run) and the growth exponent of the time in the particles.
"""

from __future__ import annotations

from ..sim.solvers import registry as solver_registry
from .accuracy_cost import bench_cost, format_cost, growth_exponent

FABRIC = "denim"
CLIP_SHARE = 16  # each clip holds 1/16 of the edge
SIZES = (32, 64, 128, 256)  # cells a side
QUICK_SIZES = (16, 32)
MAX_CELLS = 511  # cloth.resolution's 512 particles a side


def size_problem(n: int) -> str | None:
    """Why the fabric sheet cannot have `n` cells a side, or None."""
    if n < CLIP_SHARE or n % CLIP_SHARE or n > MAX_CELLS:
        return (f"the fabric sheet's size must be a multiple of {CLIP_SHARE} cells from "
                f"{CLIP_SHARE} to {MAX_CELLS - MAX_CELLS % CLIP_SHARE} (its clips hold 1/"
                f"{CLIP_SHARE} of the edge at every grid), not {n}")
    return None


def clipped_fabric_scene(n: int, overrides: dict):
    """The fabric sheet of `n` cells a side with a solver's keys."""
    from ..scene import Scene

    clip = n // CLIP_SHARE
    return Scene(name=f"{FABRIC} held by two clips").with_values({
        "cloth.size": 1.0, "cloth.resolution": n + 1, "cloth.pinned": "none",
        "cloth.height": 1.0, "scene.floor": False,
        "material": {"preset": FABRIC},
        "pins": [{"rows": [0, 0], "cols": [0, clip]},
                 {"rows": [0, 0], "cols": [-1 - clip, -1]}],
        **overrides})


def solver_runs() -> tuple[tuple[str, dict], ...]:
    """(label, keys) of every registered solver that takes a material, the registry's
    default first. The solver the default scene names runs at that scene's substeps and
    iterations (what a user gets), the others at the scene format's defaults."""
    from ..scene_files import load

    shipped = load("default").behavior
    own = solver_registry.DEFAULT
    names = solver_registry.names(takes_material=True)
    ordered = sorted(names, key=lambda name: name != own)
    runs = []
    for name in ordered:
        keys = {"behavior.solver": name}
        if name == shipped.solver:
            keys |= {"behavior.substeps": shipped.substeps,
                     "behavior.iterations": shipped.iterations}
        runs.append((name, keys))
    return tuple(runs)


def bench_fabric_cost(sizes=None, quick: bool = False, progress=lambda msg: None) -> dict:
    """Every solver that takes a material at every size, side by side."""
    sizes = list(sizes or (QUICK_SIZES if quick else SIZES))
    frames, repeats = (10, 2) if quick else (30, 2)
    out = []
    for label, overrides in solver_runs():
        rows = []
        for n in sizes:
            progress(f"cost of a fabric's accuracy: {label}, {n} cells")
            rows.append(bench_cost(n, overrides, frames, repeats,
                                   scene_for=clipped_fabric_scene))
        out.append({"solver": label, "keys": overrides, "rows": rows,
                    "exponent": growth_exponent(rows),
                    "exponent_64_256": growth_exponent(rows, lo=64, hi=256)
                    if {64, 256} <= set(sizes) else None,
                    "work_exponent": growth_exponent(rows, key="work_per_frame")})
    return {"fabric": FABRIC, "sizes": sizes, "frames": frames, "repeats": repeats,
            "solvers": out}


def format_fabric_cost(r: dict) -> list[str]:
    lines = format_cost(r)
    lines[1] = (f"Cost of a fabric's accuracy: 1 m of {r['fabric']} held by two clips, "
                f"default settings, n cells a side ((n+1)² particles), {r['frames']} frames "
                f"from flat, {r['repeats']} runs; ms per simulated frame: median "
                f"[fastest–slowest run]")
    return lines
