"""`cloth-tui bench`: performance numbers, side by side, from one run on this machine."""

from __future__ import annotations

import json
import sys

from . import breakdown as bd
from .step_bench import bare_scene, bench_step, machine


def _progress(msg: str) -> None:
    if sys.stderr.isatty():
        print(f"\r\033[K{msg}", end="", file=sys.stderr, flush=True)


def gravity_cost(n: int, quick: bool) -> dict:
    """The bare step without gravity against the same step with gravity: the cost of one
    force effect on top of integrate + constraints + pins. Measured in alternating rounds so
    drift in the machine's load hits both alike."""
    import statistics

    from ..sim import pipeline
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
    for _ in range(3 if quick else 9):
        for name, (step, state) in steps.items():
            times[name].append(time_calls(lambda: step.substep(state), block_s=0.05,
                                          blocks=3).median_s)
    bare, grav = (statistics.median(times[k]) for k in ("bare", "gravity"))
    return {"n": n, "bare_ms": bare * 1e3, "gravity_ms": grav * 1e3,
            "bare_effects": steps["bare"][0].names, "ratio": grav / bare}


def self_collision_cost(sizes: list[int], quick: bool) -> list[dict]:
    rows = []
    for mode in ("naive", "hash"):
        for n in sizes:
            _progress(f"self-collision {mode} n={n}")
            s = bare_scene(n)
            s.behavior.self_collision = mode
            s.cloth.pinned = "none"
            result = bd.breakdown(s, frames=3 if quick else 8, warmup=1)
            sc = [e for e in result["effects"] if "self" in e["effect"]]
            rows.append({"mode": mode, "n": n,
                         "ms_per_step": sc[0]["ms_per_frame"] if sc else None,
                         "effect": sc[0]["effect"] if sc else None})
    for r in rows:
        prev = next((p for p in rows if p["mode"] == r["mode"] and p["n"] * 2 == r["n"]), None)
        r["growth_vs_half_n"] = (r["ms_per_step"] / prev["ms_per_step"]
                                 if prev and prev["ms_per_step"] and r["ms_per_step"] else None)
    return rows


def run_bench(args) -> int:
    quick = args.quick
    result: dict = {"machine": machine()}
    if args.breakdown:
        from ..scene import load
        scene = load(args.breakdown)
        result["breakdown"] = bd.breakdown(scene, frames=60 if quick else 240)
    sizes = [26, 64, 128] if quick else [26, 64, 128, 256]
    steps = []
    for n in sizes:
        _progress(f"step n={n}")
        steps.append(bench_step(n, 4, quick))
    result["step"] = steps
    _progress("gravity cost")
    result["gravity_cost"] = gravity_cost(128, quick)
    result["self_collision"] = self_collision_cost([32, 64] if quick else [32, 64, 128], quick)
    from ..render.probe import RendererUnavailable
    try:
        from .render_bench import bench_render
        _progress("render")
        result["render"] = bench_render(quick)
    except (ImportError, RendererUnavailable) as e:  # the physics numbers still count
        result["render"] = {"unavailable": str(e)}
    try:
        from .frame_bench import bench_frames
        _progress("frame pipeline")
        result["frame_pipeline"] = bench_frames(quick)
    except (ImportError, RendererUnavailable) as e:
        result["frame_pipeline"] = {"unavailable": str(e)}
    result["machine"] = machine()  # threading layer is known only after a parallel kernel ran
    _progress("")
    if args.json:
        print(json.dumps(result, indent=2))
    else:
        print(format_report(result))
    return 0


def format_report(r: dict) -> str:
    m = r["machine"]
    out = [f"machine: {m['cpu']}, {m['cores']} cores; Python {m['python']}, NumPy {m['numpy']}, "
           f"numba {m['numba']} ({m['numba_threads']} threads, {m['threading_layer']})", ""]
    out.append("Bare step (corners pinned, Verlet + damping, gravity, 3 families, K = 4, no floor)")
    out.append(f"{'n':>5} {'constraints':>11} | {'compiled steps/s':>16} {'M proj/s':>9} "
               f"{'spread':>7} | {'NumPy steps/s':>13} {'M proj/s':>9} {'spread':>7} | "
               f"{'speed-up':>8} | {'compile/load s':>14}")
    for s in r["step"]:
        c, p = s["compiled"], s["numpy"]
        out.append(f"{s['n']:>5} {s['constraints']:>11} | {c['steps_per_s']:>16.0f} "
                   f"{c['mproj_per_s']:>9.1f} {c['spread']:>6.0%} | {p['steps_per_s']:>13.0f} "
                   f"{p['mproj_per_s']:>9.1f} {p['spread']:>6.0%} | {s['speedup']:>7.1f}× | "
                   f"{s['compile_or_cache_load_s']:>14.2f}")
    g = r["gravity_cost"]
    out += ["", f"Cost of gravity at n = {g['n']}: bare step ({' + '.join(g['bare_effects'])}) "
                f"{g['bare_ms']:.3f} ms/step, with gravity {g['gravity_ms']:.3f} ms/step "
                f"({(g['ratio'] - 1) * 100:+.1f} %)"]
    out += ["", "Self-collision, ms per substep (growth when n doubles)"]
    for row in r["self_collision"]:
        ms = "absent" if row["ms_per_step"] is None else f"{row['ms_per_step']:.3f} ms"
        growth = f"  ×{row['growth_vs_half_n']:.1f}" if row["growth_vs_half_n"] else ""
        out.append(f"  {row['mode']:<6} n={row['n']:<4} {ms}{growth}")
    if "breakdown" in r:
        b = r["breakdown"]
        out += ["", f"Breakdown of {b['scene']} ({b['particles']} particles, {b['substeps']} "
                    f"substeps): {b['ms_per_frame']:.3f} ms/frame"]
        for e in b["effects"]:
            out.append(f"  {e['effect']:<28} {e['ms_per_frame']:>8.3f} ms/frame "
                       f"{e['share']:>6.1%}")
    for key, title in (("render", "Render"), ("frame_pipeline", "Frame pipeline")):
        rows = r.get(key)
        out += ["", title]
        if isinstance(rows, dict):
            out.append(f"  unavailable: {rows.get('unavailable')}")
            continue
        for row in rows:
            out.append("  " + ", ".join(f"{k}={v:.2f}" if isinstance(v, float) else f"{k}={v}"
                                        for k, v in row.items()))
    return "\n".join(out)
