"""The bare step (n×n, corners pinned, Verlet with damping, gravity, all three constraint
families, K Gauss-Seidel passes, no floor), in millions of constraint projections per second:
the project's whole substep, its projection kernel alone, a plain serial numba loop of the
same step (the peer) and the plain-NumPy baseline; and whole frames per wall second."""

from __future__ import annotations

import os
import subprocess
import sys
import time
from contextlib import contextmanager

from ..scene import Scene
from ..scene_files import load
from ..sim import pipeline
from ..sim.model import build_model
from ..sim.state import ClothState
from ..sim.threads import force_single_thread
from .numpy_step import NumpyStep
from .serial_step import SerialStep
from .timing import Timing, first_call_s, time_alternating, time_calls


def bare_scene(n: int | list, iterations: int = 4) -> Scene:
    """The bare step's scene, n particles a side (or [nx, nz])."""
    s = Scene()
    s.cloth.resolution = n
    s.cloth.pinned = "corners"
    s.scene.floor = False
    s.behavior.iterations = iterations
    s.behavior.substeps = 1
    s.behavior.tethers = False  # the bare step: integrate, constraints, pins, velocities
    s.behavior.solver = "pbd"  # K Gauss-Seidel passes, as the serial peer runs them
    return s


def _rate(timing: Timing, work: float) -> dict:
    """Work per second (median, and the slowest and fastest block) with the raw timing."""
    return {**timing.as_dict(), "per_s": work / timing.median_s,
            "per_s_min": work / timing.max_s, "per_s_max": work / timing.min_s}


def bench_step(n: int, iterations: int = 4, quick: bool = False,
               numpy_baseline: bool = True) -> dict:
    scene = bare_scene(n, iterations)
    model = build_model(scene.cloth, scene.behavior)
    step = pipeline.build(scene, model)
    state = ClothState.from_model(model)
    compile_s = first_call_s(lambda: step.substep(state))
    projection = next(e for e in step.effects if e.name == "project_constraints")
    b = scene.behavior
    peer = SerialStep(model, step.h, iterations, b.damping, scene.forces.gravity_strength,
                      b.max_speed)
    peer_state = ClothState.from_model(model)
    peer.substep(peer_state)  # compile or load
    blocks, block_s = (3, 0.05) if quick else (7, 0.2)
    choice = projection.kernels
    calls0, parallel0 = choice.calls, choice.parallel_calls
    t = time_alternating({"step": lambda: step.substep(state),
                          "kernel": lambda: projection.apply(state, step.h),
                          "serial_loop": lambda: peer.substep(peer_state)},
                         block_s=block_s, blocks=blocks)
    projections = model.num_constraints * iterations / 1e6  # M projections per step
    # One thread each, CPU time of this thread: the kernels' own speed, whatever the load
    force_single_thread(True)
    try:
        cpu = time_alternating({"step": lambda: step.substep(state),
                                "serial_loop": lambda: peer.substep(peer_state)},
                               block_s=block_s, blocks=blocks, clock=time.thread_time)
    finally:
        force_single_thread(False)
    out = {
        "n": n, "iterations": iterations, "constraints": model.num_constraints,
        "effects": step.names, "projection_kernel": projection.kernel_name,
        "parallel_share": (choice.parallel_calls - parallel0) / max(1, choice.calls - calls0),
        "compile_or_cache_load_s": compile_s,
        "step": _rate(t["step"], projections), "kernel": _rate(t["kernel"], projections),
        "serial_loop": _rate(t["serial_loop"], projections),
        "step_vs_serial_loop": t["serial_loop"].median_s / t["step"].median_s,
        "one_thread_cpu": {"step": _rate(cpu["step"], projections),
                           "serial_loop": _rate(cpu["serial_loop"], projections),
                           "step_vs_serial_loop": cpu["serial_loop"].median_s
                           / cpu["step"].median_s},
    }
    if numpy_baseline:
        ref = NumpyStep(model, step.h, iterations, b.damping, scene.forces.gravity_strength,
                        b.max_speed)
        s2 = ClothState.from_model(model)
        baseline = time_calls(lambda: ref.substep(s2.x, s2.x_prev, s2.v, s2.anchors),
                              block_s=block_s, blocks=blocks, warmup=1)
        out["numpy"] = _rate(baseline, projections)
    return out


def frame_scene(n: int, substeps: int = 4, iterations: int = 4) -> Scene:
    """The original scene at n×n with pbd's fixed substeps × passes (adaptive off), tethers
    and floor on: the step's throughput, which the cost-of-accuracy table does not show."""
    return load("original").with_values({
        "cloth.resolution": n, "behavior.solver": "pbd", "behavior.substeps": substeps,
        "behavior.iterations": iterations, "behavior.adaptive": False})


def bench_frames_per_second(n: int = 256, substeps: int = 4, iterations: int = 4,
                            quick: bool = False) -> dict:
    """Simulated frames per wall second (Simulation.advance_frame: step, health checks, undo
    copy) of frame_scene, over timed blocks after a warm-up."""
    from ..sim.run.runner import Simulation

    sim = Simulation(frame_scene(n, substeps, iterations))
    blocks, block_s = (3, 0.1) if quick else (5, 1.0)
    timing = time_calls(sim.advance_frame, block_s=block_s, blocks=blocks, warmup=3)
    projection = next(e for e in sim.step.effects if e.name == "project_constraints")
    return {"n": n, "substeps": sim.step.substeps, "iterations": iterations,
            "adaptive": False, "effects": sim.step.names, "threads": projection.threads,
            **_rate(timing, 1.0)}


@contextmanager
def busy_core():
    """A CPU-bound busy loop in its own process for the duration (one core taken)."""
    proc = subprocess.Popen([sys.executable, "-c", "while True: pass"],
                            stdin=subprocess.DEVNULL, stdout=subprocess.DEVNULL,
                            stderr=subprocess.DEVNULL)
    try:
        time.sleep(0.2)  # let it start spinning
        yield proc.pid
    finally:
        proc.kill()
        proc.wait()


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
    load1 = os.getloadavg()[0] if hasattr(os, "getloadavg") else float("nan")
    return {"cpu": cpu, "cores": os.cpu_count(), "python": platform.python_version(),
            "numpy": numpy.__version__, "numba": numba.__version__,
            "numba_threads": numba.get_num_threads(),
            "threading_layer": _threading_layer(), "load_1min": load1,
            "CLOTH_TUI_THREADS": os.environ.get("CLOTH_TUI_THREADS")}


def _threading_layer() -> str:
    import numba
    try:
        return numba.threading_layer()
    except ValueError:  # no parallel kernel has run yet
        return "not initialised"
