"""One wedge run, as a task on a Dask worker: simulate the cell's scene and render it (the
last frame, or every frame for a clip). Each worker process keeps its renderers between
tasks (a GL context costs ~0.5 s) and its compiled kernels (numba keeps them per process),
so only a worker's first task pays for them."""

from __future__ import annotations

import os
import socket
import threading
import time

import numpy as np

from ..scene import Scene

# (thread, size) → Renderer: VTK's GL context is bound to the thread that made it, and a
# worker runs its tasks on its own thread(s).
_RENDERERS: dict = {}


def _renderer(scene: Scene, size: tuple[int, int]):
    from ..render.renderer import Renderer

    key = (threading.get_ident(), tuple(size))
    r = _RENDERERS.get(key)
    if r is None:
        r = _RENDERERS[key] = Renderer(scene, size)
    else:
        r.update_scene(scene)
    r.reset_camera()  # the previous cell's sheet size or auto-rotation must not carry over
    return r


def run_cell(scene: Scene, frames: int, size: tuple[int, int], video: bool) -> dict:
    """Simulate `frames` frames and render. Returns the run's measures (JSON-ready), and
    `image` ((H, W, 3) uint8, the last frame) or `clip` ((frames, H, W, 3) uint8)."""
    from ..sim.run.runner import Simulation

    started = time.perf_counter()
    sim = Simulation(scene)
    sim.advance_frame()  # compiles (or loads cached) kernels; not counted in wall_s
    sim.reset()
    e0 = sim.stats().energy
    renderer = _renderer(scene, size)
    clip = []
    for _ in range(frames):
        sim.advance_frame()
        if video:
            clip.append(renderer.render(sim.snapshot()))
    stats = sim.stats()
    image = None if video else renderer.render(sim.snapshot(stats))
    return {
        "max_stretch": stats.max_stretch,
        "energy_drift": stats.energy - e0,       # J, since the first frame
        "penetration": stats.penetration,
        "recoveries": stats.recoveries,
        "substeps_used": stats.substeps_used,
        "halted": stats.halted,
        "finite": stats.finite,
        "wall_s": stats.wall_s,                   # stepping only, as `simulate` reports
        "task_s": time.perf_counter() - started,     # with start-up and rendering
        "worker": f"{socket.gethostname()}:{os.getpid()}",
        "image": image,
        "clip": np.stack(clip) if video else None,
    }
