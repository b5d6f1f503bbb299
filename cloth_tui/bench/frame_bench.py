"""The whole frame as the app makes it: advance the simulation one frame, render the
snapshot off-screen, encode the image as the terminal preview's half-block strips.

Timed serially in one thread, so the sum is an upper bound: in the app the simulation and the
renderer run on their own threads and overlap."""

from __future__ import annotations

import statistics
import time

# The preview of a 160×48 terminal (render_bench's, checked against the app by a test):
# cells of 1×2 pixels, drawn by the renderer at SCALE times that and averaged down.
from .render_bench import PREVIEW_CELLS


def bench_frames(quick: bool = False) -> list[dict]:
    from ..render.renderer import Renderer
    from ..scene_files import load
    from ..tui.preview import SCALE, RowCache, StyleCache, image_to_strips

    cols, rows = PREVIEW_CELLS
    width, height = cols * SCALE, 2 * rows * SCALE
    # 128² and 256² at the scene's own fixed substeps (adaptive off): a frame's cost, not the
    # accuracy control's choice of substeps during the fall
    cases = [("default", {}),
             ("default 128×128", {"cloth.resolution": 128, "behavior.adaptive": False}),
             ("default 256×256", {"cloth.resolution": 256, "behavior.adaptive": False})]
    frames = 30 if quick else 120
    out = []
    for label, overrides in cases:
        from ..sim.run.runner import Simulation

        scene = load("default")
        for k, v in overrides.items():
            scene = scene.with_value(k, v)
        sim = Simulation(scene)
        renderer = Renderer(scene, (width, height))
        styles, rows_kept = StyleCache(), RowCache()  # as the app's preview keeps them
        try:
            for _ in range(5):  # warm-up: kernels, shaders, style cache
                sim.advance_frame()
                image_to_strips(renderer.render(sim.snapshot()), cols, rows, styles,
                                cache=rows_kept)
            sim_t, render_t, encode_t = [], [], []
            for _ in range(frames):
                t0 = time.perf_counter()
                sim.advance_frame()
                snap = sim.snapshot()
                t1 = time.perf_counter()
                image = renderer.render(snap)
                t2 = time.perf_counter()
                image_to_strips(image, cols, rows, styles, cache=rows_kept)
                t3 = time.perf_counter()
                sim_t.append(t1 - t0)
                render_t.append(t2 - t1)
                encode_t.append(t3 - t2)
        finally:
            renderer.close()
        total = [a + b + c for a, b, c in zip(sim_t, render_t, encode_t)]
        med = statistics.median(total)
        out.append({"bench": "frame", "scene": label, "substeps": sim.step.substeps,
                    "image": f"{width}x{height}", "cells": f"{cols}x{rows}",
                    "simulate_ms": 1e3 * statistics.median(sim_t),
                    "render_ms": 1e3 * statistics.median(render_t),
                    "encode_ms": 1e3 * statistics.median(encode_t),
                    "total_ms": 1e3 * med,
                    "total_p90_ms": 1e3 * sorted(total)[int(0.9 * len(total))],
                    "fps_serial": 1.0 / med,
                    "sim_frames_per_s": 1.0 / statistics.median(sim_t)})
    return out
