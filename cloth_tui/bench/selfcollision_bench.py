"""Self-collision on a crumpled sheet: the sheet folded like an accordion three times each
way, so nine layers lie over one another a collision distance apart. A flat sheet is the
spatial hash's best case (one layer per cell); this is closer to a sheet dropped in a heap."""

from __future__ import annotations

import statistics
import time

import numpy as np

from ..sim.model import build_model
from ..sim.collision.selfcollision import SelfCollision
from ..sim.state import ClothState
from .step_bench import bare_scene

FOLDS = 3  # per direction


def crumpled(model, gap: float) -> np.ndarray:
    """Positions of the sheet folded FOLDS times along each axis, layers `gap` apart."""
    ux, uz = np.linspace(0.0, FOLDS, model.nx), np.linspace(0.0, FOLDS, model.nz)
    tri_x, tri_z = np.abs(ux % 2.0 - 1.0), np.abs(uz % 2.0 - 1.0)  # 0…1…0: the accordion
    layer_x = np.minimum(np.floor(ux), FOLDS - 1)
    layer_z = np.minimum(np.floor(uz), FOLDS - 1)
    x = np.empty(model.shape + (3,))
    x[..., 0] = model.width / FOLDS * tri_x[None, :]
    x[..., 2] = model.length / FOLDS * tri_z[:, None]
    x[..., 1] = model.rest_positions[0, 1] + gap * (layer_x[None, :] + FOLDS * layer_z[:, None])
    return x.reshape(-1, 3)


def bench_self_collision(sizes_by_method: dict[str, list[int]], quick: bool) -> list[dict]:
    rows = []
    for method, sizes in sizes_by_method.items():
        for n in sizes:
            scene = bare_scene(n)
            scene.cloth.pinned = "none"
            model = build_model(scene.cloth, scene.behavior)
            effect = SelfCollision(model, method)
            start = crumpled(model, 0.5 * effect.distance)
            state = ClothState.from_model(model)
            pairs = effect.find_pairs(start)
            per_call = []
            for _ in range(3 if quick else 7):
                total, calls = 0.0, 0
                while total < (0.02 if quick else 0.1) or calls < 2:
                    state.x[...] = start
                    t0 = time.perf_counter()
                    effect.apply(state, 1e-3)
                    total += time.perf_counter() - t0
                    calls += 1
                per_call.append(total / calls)
            rows.append({"method": method, "n": n, "pairs": pairs,
                         "ms_per_substep": 1e3 * statistics.median(per_call),
                         "ms_min": 1e3 * min(per_call), "ms_max": 1e3 * max(per_call)})
    for r in rows:
        prev = next((p for p in rows if p["method"] == r["method"] and 2 * p["n"] == r["n"]),
                    None)
        r["growth_vs_half_n"] = r["ms_per_substep"] / prev["ms_per_substep"] if prev else None
    return rows
