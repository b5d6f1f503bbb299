"""How long one rendered frame takes: update the mesh in place, draw off-screen, read the
pixels back and anti-alias them: `Renderer.render`, as the app's render thread calls it.
Numbers, not a test; `cloth-tui bench` calls `bench_render`.

Both wall-clock and CPU time (`time.process_time`, all the process's threads, Mesa's
rasteriser threads included) are reported: on a shared machine the wall time mostly measures
the other programs, the CPU time what a frame costs."""

from __future__ import annotations

import statistics
import time

SHEETS = (26, 128, 256)
TERMINAL = (160, 48)         # the terminal the app is measured in (tmux; docs/app.md)
PREVIEW_CELLS = (114, 45)    # the app's preview widget there (tests/bench checks it)
PIXEL_CELL_PX = (10, 20)     # a typical cell, and the app's guess when the terminal tells none
REFERENCE_SIZE = (640, 384)  # the size earlier bench runs (and the README) used
SETTLE_FRAMES = 20


def preview_sizes() -> list[tuple[str, tuple[int, int]]]:
    """The pixel sizes the app renders its live preview at in a TERMINAL-sized terminal, as
    the preview widgets ask the renderer for them, labelled; then REFERENCE_SIZE."""
    from ..tui.pixel_preview import render_size
    from ..tui.preview import SCALE

    cols, rows = PREVIEW_CELLS
    term = f"{TERMINAL[0]}×{TERMINAL[1]}"
    cell = f"{PIXEL_CELL_PX[0]}×{PIXEL_CELL_PX[1]} px cells"
    return [(f"blocks preview {term}", (SCALE * cols, SCALE * 2 * rows)),
            (f"kitty preview {term}, {cell}", render_size(cols, rows, PIXEL_CELL_PX, "kitty")),
            ("reference: earlier runs' size", REFERENCE_SIZE)]


def _snapshots(resolution: int):
    """Two draped states of a sheet, alternated so every frame really moves the mesh."""
    from ..scene import Scene
    from ..sim.run.runner import Simulation

    scene = Scene().with_value("cloth.resolution", resolution)
    sim = Simulation(scene)
    for _ in range(SETTLE_FRAMES):
        sim.advance_frame()
    a = sim.snapshot()
    sim.advance_frame()
    return scene, (a, sim.snapshot())


def time_frames(renderer, snaps, blocks: int, per_block: int) -> tuple[list, list]:
    """ms per frame (wall, CPU) for each of `blocks` blocks of `per_block` frames."""
    wall, cpu = [], []
    for _ in range(blocks):
        t0, c0 = time.perf_counter(), time.process_time()
        for k in range(per_block):
            renderer.render(snaps[k % 2])
        wall.append((time.perf_counter() - t0) * 1e3 / per_block)
        cpu.append((time.process_time() - c0) * 1e3 / per_block)
    return wall, cpu


def bench_render(quick: bool = False, sheets=SHEETS, views=None) -> list[dict]:
    """ms per frame for each sheet × labelled image size (`views`: (label, (w, h)) pairs,
    by default preview_sizes()): medians over timed blocks after a warm-up, with the
    fastest and slowest block's wall time as the spread."""
    from ..render.renderer import Renderer

    views = preview_sizes() if views is None else list(views)
    blocks, per_block = (3, 5) if quick else (7, 10)
    rows = []
    for n in sheets:
        scene, snaps = _snapshots(n)
        renderer = Renderer(scene, views[0][1])
        try:
            for view, (w, h) in views:
                renderer.resize(w, h)
                renderer.reset_camera()
                for k in range(3):  # warm-up: shader compilation, buffer allocation
                    renderer.render(snaps[k % 2])
                wall, cpu = time_frames(renderer, snaps, blocks, per_block)
                rows.append({
                    "bench": "render",
                    "resolution": n,
                    "particles": n * n,
                    "view": view,
                    "size": f"{w}x{h}",
                    "ms_per_frame": round(statistics.median(wall), 3),
                    "cpu_ms_per_frame": round(statistics.median(cpu), 3),
                    "ms_min": round(min(wall), 3),
                    "ms_max": round(max(wall), 3),
                    "blocks": blocks,
                    "frames_per_block": per_block,
                })
        finally:
            renderer.close()
    return rows


def format_rows(rows: list[dict]) -> str:
    width = max([len(r["view"]) for r in rows] + [4])
    lines = [f"{'sheet':>9} {'view':<{width}} {'image':>9} {'ms/frame':>9} {'cpu ms':>7} "
             f"{'min':>7} {'max':>7}"]
    for r in rows:
        lines.append(f"{r['resolution']:>4}x{r['resolution']:<4} {r['view']:<{width}} "
                     f"{r['size']:>9} {r['ms_per_frame']:>9.2f} {r['cpu_ms_per_frame']:>7.2f} "
                     f"{r['ms_min']:>7.2f} {r['ms_max']:>7.2f}")
    return "\n".join(lines)


if __name__ == "__main__":
    import sys
    print(format_rows(bench_render(quick="--quick" in sys.argv)))
