"""Self-collision on a crumpled sheet: the sheet folded like an accordion three times each
way, so nine layers lie over one another a collision distance apart. A flat sheet is the
spatial hash's best case (one layer per cell); this is closer to a sheet dropped in a heap."""

from __future__ import annotations

import statistics
import time

import numpy as np

from ..sim.model import build_model
from ..sim.selfcollision import SelfCollision
from ..sim.state import ClothState
from .step_bench import bare_scene

FOLDS = 3  # per direction


def crumpled(model, gap: float) -> np.ndarray:
    """Positions of the sheet folded FOLDS times along each axis, layers `gap` apart."""
    n, size = model.n, model.size
    u = np.linspace(0.0, FOLDS, n)
    tri = np.abs(u % 2.0 - 1.0)          # 0…1…0: the accordion
    layer = np.minimum(np.floor(u), FOLDS - 1)
    x = np.empty((n, n, 3))
    x[..., 0] = size / FOLDS * tri[None, :]
    x[..., 2] = size / FOLDS * tri[:, None]
    x[..., 1] = model.rest_positions[0, 1] + gap * (layer[None, :] + FOLDS * layer[:, None])
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
