"""How long an edit of a setting holds the app's UI thread: the handler of one field's edit
(validation, handing the scene to the simulation and renderer threads, the field's text),
timed on the UI thread of a headless app (Textual's run_test, no renderer: the renderer's
share is queueing one command), the field's text already as typed. The simulation thread
applies the edit later, on its own thread. Wall time includes waiting for the GIL while the
simulation thread, woken by the edit, applies it; CPU time is the UI thread's own work.

    python tools/edit_latency.py                 # the keys of docs/app.md, 200 edits each
    python tools/edit_latency.py --edits 50 --json

A benchmark, not a test: it prints numbers. Exit status 0, or 2 for bad arguments.
"""

from __future__ import annotations

import argparse
import asyncio
import json
import statistics
import sys
import tempfile
import time
from pathlib import Path

# (key, two values it alternates between); the parameters the running step reads, and a
# key that changes the step (wind on/off) for comparison; then an object's friction, edited
# in the objects panel
KEYS = [("forces.wind_strength", 3.0, 5.0), ("forces.gravity_strength", 9.81, 4.0),
        ("scene.friction", 0.9, 0.3), ("behavior.damping", 0.03, 0.1),
        ("forces.wind", True, False)]


SPHERE = {"type": "sphere", "center": [0.0, -0.1, 0.0], "radius": 0.3}


def _no_renderer(**_):
    raise RuntimeError("not measured")


async def _measure(edits: int) -> dict[str, tuple[list[float], list[float]]]:
    from cloth_tui.scene import Scene
    from cloth_tui.tui.app import ClothApp
    from textual.widgets import Input, Switch

    from cloth_tui.tui.panels import ObjectsPanel, SettingField, format_value, widget_id

    scene = Scene().with_values({"forces.wind": True}).with_objects([SPHERE])
    app = ClothApp(scene, Path(tempfile.mkdtemp()) / "caps", renderer_factory=_no_renderer,
                   start_paused=True)
    out: dict[str, tuple[list[float], list[float]]] = {}
    async with app.run_test(size=(160, 48)) as pilot:
        while app.sim is None:
            await pilot.pause(0.05)
        for dotted, a, b in KEYS:
            row = app.query_one("#" + widget_id(dotted) + "-row", SettingField)
            wall, cpu = out.setdefault(dotted, ([], []))
            for k in range(edits):
                value = b if k % 2 == 0 else a
                control = row.control  # as typing (or a click) leaves it, before the edit
                with control.prevent(Input.Changed, Switch.Changed):
                    control.value = value if isinstance(control, Switch) else format_value(value)
                message = SettingField.Edited(row, dotted, value)
                t0, c0 = time.perf_counter(), time.thread_time()
                app.on_setting_field_edited(message)
                cpu.append(time.thread_time() - c0)
                wall.append(time.perf_counter() - t0)
                if k % 20 == 19:
                    await pilot.pause(0)  # let the simulation thread drain its commands
        wall, cpu = out.setdefault("objects[0].friction", ([], []))
        for k in range(edits):  # the objects panel's edit: the whole list, one value new
            table = {**SPHERE, "friction": 0.2 if k % 2 == 0 else 0.7}
            message = ObjectsPanel.Changed([table])
            t0, c0 = time.perf_counter(), time.thread_time()
            app.on_objects_panel_changed(message)
            cpu.append(time.thread_time() - c0)
            wall.append(time.perf_counter() - t0)
            if k % 20 == 19:
                await pilot.pause(0)
    return out


def _p95(values: list[float]) -> float:
    return sorted(values)[int(0.95 * (len(values) - 1))]


def main(argv: list[str] | None = None) -> int:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--edits", type=int, default=200, help="edits per key (default 200)")
    parser.add_argument("--json", action="store_true", help="print the numbers as JSON")
    args = parser.parse_args(argv)
    if args.edits < 2:
        print("edit_latency: --edits must be at least 2", file=sys.stderr)
        return 2
    times = asyncio.run(_measure(args.edits))
    rows = {k: {"median_ms": 1e3 * statistics.median(wall), "p95_ms": 1e3 * _p95(wall),
                "max_ms": 1e3 * max(wall), "cpu_median_ms": 1e3 * statistics.median(cpu),
                "cpu_p95_ms": 1e3 * _p95(cpu), "edits": len(wall)}
            for k, (wall, cpu) in times.items()}
    if args.json:
        print(json.dumps(rows, indent=2))
    else:
        print("ms of the UI thread per edit: wall time (median, p95, max), and the thread's "
              "own CPU time (median, p95)")
        print(f"{'key':26} {'median':>7} {'p95':>7} {'max':>7} {'cpu':>7} {'cpu p95':>7}")
        for k, r in rows.items():
            print(f"{k:26} {r['median_ms']:7.3f} {r['p95_ms']:7.3f} {r['max_ms']:7.3f} "
                  f"{r['cpu_median_ms']:7.3f} {r['cpu_p95_ms']:7.3f}")
    return 0


if __name__ == "__main__":
    sys.exit(main())
