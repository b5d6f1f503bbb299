"""The bare step (n×n, corners pinned, Verlet with damping, gravity, all three constraint
families, K Gauss-Seidel passes, no floor): the project's compiled step against its plain-
NumPy baseline, in steps per second and millions of constraint projections per second."""

from __future__ import annotations

import os

from ..scene import Scene
from ..sim import pipeline
from ..sim.model import build_model
from ..sim.state import ClothState
from .numpy_step import NumpyStep
from .timing import first_call_s, time_calls


def bare_scene(n: int, iterations: int = 4) -> Scene:
    s = Scene()
    s.cloth.resolution = n
    s.cloth.pinned = "corners"
    s.scene.floor = False
    s.behavior.iterations = iterations
    s.behavior.substeps = 1
    s.behavior.tethers = False  # the bare step: integrate, constraints, pins, velocities
    return s


def bench_step(n: int, iterations: int = 4, quick: bool = False) -> dict:
    scene = bare_scene(n, iterations)
    model = build_model(scene.cloth, scene.behavior)
    step = pipeline.build(scene, model)
    state = ClothState.from_model(model)
    compile_s = first_call_s(lambda: step.substep(state))
    blocks, block_s = (3, 0.1) if quick else (7, 0.25)
    compiled = time_calls(lambda: step.substep(state), block_s=block_s, blocks=blocks)

    b = scene.behavior
    ref = NumpyStep(model, step.h, iterations, b.damping, scene.forces.gravity_strength,
                    b.max_speed)
    s2 = ClothState.from_model(model)
    baseline = time_calls(lambda: ref.substep(s2.x, s2.x_prev, s2.v, s2.anchors),
                          block_s=block_s, blocks=blocks, warmup=1)
    projections = model.num_constraints * iterations
    kernel = next(e.kernel_name for e in step.effects if e.name == "project_constraints")
    return {
        "n": n, "iterations": iterations, "constraints": model.num_constraints,
        "effects": step.names, "projection_kernel": kernel,
        "compile_or_cache_load_s": compile_s,
        "compiled": {**compiled.as_dict(), "steps_per_s": 1.0 / compiled.median_s,
                     "mproj_per_s": projections / compiled.median_s / 1e6},
        "numpy": {**baseline.as_dict(), "steps_per_s": 1.0 / baseline.median_s,
                  "mproj_per_s": projections / baseline.median_s / 1e6},
        "speedup": baseline.median_s / compiled.median_s,
    }


def machine() -> dict:
    import platform

    import numba
    import numpy

    cpu = platform.processor() or platform.machine()
    try:
        with open("/proc/cpuinfo") as fh:
            cpu = next(line.split(":", 1)[1].strip() for line in fh if "model name" in line)
    except (OSError, StopIteration):
        pass
    return {"cpu": cpu, "cores": os.cpu_count(), "python": platform.python_version(),
            "numpy": numpy.__version__, "numba": numba.__version__,
            "numba_threads": numba.get_num_threads(),
            "threading_layer": _threading_layer()}


def _threading_layer() -> str:
    import numba
    try:
        return numba.threading_layer()
    except ValueError:  # no parallel kernel has run yet
        return "not initialised"
