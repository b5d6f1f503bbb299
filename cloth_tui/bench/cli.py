"""`cloth-tui bench`: performance numbers, side by side, from one run on this machine.

Every figure is a median over timed blocks after a warm-up, shown with the slowest and the
fastest block ([min–max]). Wall-clock figures depend on what else the machine runs: the
report prints the load average at the start and the end."""

from __future__ import annotations

import json
import sys

from . import breakdown as bd
from .accuracy_cost import bench_accuracy_cost, format_cost
from .fabric_cost import bench_fabric_cost, format_fabric_cost
from .render_bench import format_rows as format_render_rows
from .step_bench import bare_scene, bench_frames_per_second, bench_step, busy_core, machine

FRAME_SHEET = 256  # the frames-per-second target's sheet: 4 substeps × 4 iterations


def _progress(msg: str) -> None:
    if sys.stderr.isatty():
        print(f"\r\033[K{msg}", end="", file=sys.stderr, flush=True)


def gravity_cost(n: int, quick: bool) -> dict:
    """The bare step without gravity against the same step with gravity: the cost of one
    force effect on top of integrate + constraints + pins. Measured in alternating rounds so
    drift in the machine's load hits both alike, both on one thread: the thread picker's
    choices, which differ between the two steps, made gravity look 7 % cheaper than none."""
    import statistics

    from ..sim import pipeline, threads
    from ..sim.model import build_model
    from ..sim.state import ClothState
    from .timing import time_calls

    steps = {}
    for name, gravity in (("bare", False), ("gravity", True)):
        scene = bare_scene(n)
        scene.forces.gravity = gravity
        model = build_model(scene.cloth, scene.behavior)
        step, state = pipeline.build(scene, model), ClothState.from_model(model)
        steps[name] = (step, state)
    times = {"bare": [], "gravity": []}
    forced = threads.single_thread_forced()
    threads.force_single_thread(True)
    try:
        for _ in range(3 if quick else 9):
            for name, (step, state) in steps.items():
                times[name].append(time_calls(lambda: step.substep(state), block_s=0.05,
                                              blocks=3).median_s)
    finally:
        threads.force_single_thread(forced)
    bare, grav = (statistics.median(times[k]) for k in ("bare", "gravity"))
    return {"n": n, "bare_ms": bare * 1e3, "gravity_ms": grav * 1e3,
            "bare_effects": steps["bare"][0].names, "ratio": grav / bare}


def _steps(sizes: list[int], quick: bool, label: str) -> dict:
    rows = []
    for n in sizes:
        _progress(f"{label}: step n={n}")
        rows.append(bench_step(n, 4, quick, numpy_baseline=label == "quiet"))
    frame_n = min(FRAME_SHEET, max(sizes))
    _progress(f"{label}: frames per second at {frame_n}²")
    return {"step": rows, "frames": bench_frames_per_second(frame_n, quick=quick)}


def run_bench(args) -> int:
    from .selfcollision_bench import bench_self_collision

    quick = args.quick
    sizes = args.sizes or ([26, 64, 128] if quick else [26, 64, 128, 256])
    result: dict = {"machine_start": machine()}
    if args.breakdown:
        from ..scene_files import load
        scene = load(args.breakdown)
        result["breakdown"] = bd.breakdown(scene, frames=60 if quick else 240)
    result["quiet"] = _steps(sizes, quick, "quiet")
    if not args.no_cost:
        result["accuracy_cost"] = bench_accuracy_cost(args.cost_sizes or args.sizes, quick,
                                                       _progress)
    if not args.no_fabric:
        result["fabric_cost"] = bench_fabric_cost(args.fabric_sizes, quick, _progress)
    if args.contended:
        with busy_core() as pid:
            result["contended"] = {"busy_pid": pid, **_steps(sizes, quick, "contended")}
    _progress("gravity cost")
    result["gravity_cost"] = gravity_cost(min(128, max(sizes)), quick)
    _progress("self-collision")
    small = [n for n in (32, 64, 128) if n <= max(sizes)] or [min(sizes)]
    result["self_collision"] = bench_self_collision(
        {"naive": small[:2], "hash": small}, quick)
    if not args.no_render:
        _render_benches(result, quick)
    result["machine"] = machine()  # threading layer is known only after a parallel kernel ran
    result["vectors"] = _vectors(quick)
    _progress("")
    print(json.dumps(result, indent=2) if args.json else format_report(result))
    return 0


def _vectors(quick: bool) -> dict:
    from .vector_code import cpu_vectors, projection_kernel_ops
    _progress("the projection kernel's instructions")
    # a fresh compile takes seconds: full runs only
    return {**cpu_vectors(), "projection_kernel_ops": None if quick else projection_kernel_ops()}


def _render_benches(result: dict, quick: bool) -> None:
    from ..render.probe import RendererUnavailable
    try:
        from .render_bench import bench_render
        _progress("render")
        result["render"] = bench_render(quick, sheets=(26, 128, 256))
    except (ImportError, RendererUnavailable) as e:  # the physics numbers still count
        result["render"] = {"unavailable": str(e)}
    try:
        from .frame_bench import bench_frames
        _progress("frame pipeline")
        result["frame_pipeline"] = bench_frames(quick)
    except (ImportError, RendererUnavailable) as e:
        result["frame_pipeline"] = {"unavailable": str(e)}


def _spread(r: dict, fmt: str = ".0f") -> str:
    return f"{r['per_s']:{fmt}} [{r['per_s_min']:{fmt}}–{r['per_s_max']:{fmt}}]"


def _threads(row: dict) -> str:
    share = row["parallel_share"]
    return "1" if share == 0 else "2" if share == 1 else f"2 on {share:.1%}"


def _one_thread(c: dict) -> str:
    return f"{c['step']['per_s']:.0f} ÷ {c['serial_loop']['per_s']:.0f} = " \
           f"{c['step_vs_serial_loop']:.2f}×"


def _step_table(title: str, part: dict) -> list[str]:
    out = ["", title,
           f"{'n':>5} {'constraints':>11} {'threads':>9} | {'whole step':>19} | "
           f"{'kernel alone':>19} | {'serial numba loop':>19} | {'step ÷ loop':>11} | "
           f"{'1 thread, CPU time: step ÷ loop':>31} | {'NumPy':>12}"]
    for s in part["step"]:
        numpy = _spread(s["numpy"], ".1f") if "numpy" in s else "–"
        out.append(f"{s['n']:>5} {s['constraints']:>11} {_threads(s):>9} | "
                   f"{_spread(s['step']):>19} | {_spread(s['kernel']):>19} | "
                   f"{_spread(s['serial_loop']):>19} | {s['step_vs_serial_loop']:>10.2f}× | "
                   f"{_one_thread(s['one_thread_cpu']):>31} | {numpy:>12}")
    f = part["frames"]
    out.append(f"  {f['n']}² sheet, original scene, {f['substeps']} substeps × {f['iterations']} "
               f"iterations, fixed (adaptive off), {f['threads']} thread(s) at the end: "
               f"{_spread(f, '.1f')} simulated frames per wall second")
    return out


def format_report(r: dict) -> str:
    m, m0 = r["machine"], r["machine_start"]
    out = [f"machine: {m['cpu']}, {m['cores']} cores; Python {m['python']}, NumPy {m['numpy']}, "
           f"numba {m['numba']} ({m['numba_threads']} threads, {m['threading_layer']} layer); "
           f"CLOTH_TUI_THREADS={m['CLOTH_TUI_THREADS'] or 'unset'}",
           f"load average (1 min): {m0['load_1min']:.2f} at the start, {m['load_1min']:.2f} "
           f"at the end. Figures: median [slowest–fastest block], wall clock."]
    if "vectors" in r:
        from .vector_code import describe
        out.append(describe(r["vectors"], r["vectors"]["projection_kernel_ops"]))
    head = ("M constraint projections per second; bare step (corners pinned, Verlet + "
            "damping, gravity, 3 families, K = 4, no floor). 'whole step' = every stage of "
            "a substep; 'kernel alone' = the projection stage only")
    out += _step_table(f"Step, {head}", r["quiet"])
    if "contended" in r:
        out += _step_table("Step with a busy loop taking one core (--contended)",
                           r["contended"])
    if "accuracy_cost" in r:
        out += format_cost(r["accuracy_cost"])
    if "fabric_cost" in r:
        out += format_fabric_cost(r["fabric_cost"])
    g = r["gravity_cost"]
    out += ["", f"Cost of gravity at n = {g['n']}, one thread: bare step "
                f"({' + '.join(g['bare_effects'])}) {g['bare_ms']:.3f} ms/step, "
                f"with gravity {g['gravity_ms']:.3f} ms/step "
                f"({(g['ratio'] - 1) * 100:+.1f} %)"]
    out += ["", "Self-collision on a crumpled sheet (folded 3×3, nine layers), ms per substep"]
    for row in r["self_collision"]:
        growth = f"  ×{row['growth_vs_half_n']:.1f} for 2× n" if row["growth_vs_half_n"] else ""
        out.append(f"  {row['method']:<6} n={row['n']:<4} {row['ms_per_substep']:.3f} ms "
                   f"[{row['ms_min']:.3f}–{row['ms_max']:.3f}], {row['pairs']} pairs{growth}")
    if "breakdown" in r:
        b = r["breakdown"]
        out += ["", f"Breakdown of {b['scene']} ({b['particles']} particles, {b['substeps']} "
                    f"substeps): {b['ms_per_frame']:.3f} ms/frame"]
        for e in b["effects"]:
            out.append(f"  {e['effect']:<28} {e['ms_per_frame']:>8.3f} ms/frame "
                       f"{e['share']:>6.1%}")
    for key, title in (("render", "Render (Renderer.render: mesh update, draw, read-back, "
                                  "anti-aliasing), ms per frame, wall and CPU"),
                       ("frame_pipeline", "Frame pipeline")):
        if key not in r:
            continue
        rows = r[key]
        out += ["", title]
        if isinstance(rows, dict):
            out.append(f"  unavailable: {rows.get('unavailable')}")
            continue
        if key == "render":
            out += ["  " + line for line in format_render_rows(rows).splitlines()]
            continue
        for row in rows:
            out.append("  " + ", ".join(f"{k}={v:.2f}" if isinstance(v, float) else f"{k}={v}"
                                        for k, v in row.items()))
    return "\n".join(out)
