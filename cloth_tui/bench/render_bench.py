"""How long one rendered frame takes: update the mesh in place, draw off-screen, read the
pixels back. Numbers, not a test; `cloth-tui bench` calls `bench_render`."""

from __future__ import annotations

import statistics
import time

SHEETS = (26, 128)
SIZES = ((320, 240), (640, 480))


def _snapshots(resolution: int):
    """Two draped states of a sheet, alternated so every frame really moves the mesh."""
    from ..scene import Scene
    from ..sim.runner import Simulation

    scene = Scene().with_value("cloth.resolution", resolution)
    sim = Simulation(scene)
    for _ in range(20):
        sim.advance_frame()
    a = sim.snapshot()
    sim.advance_frame()
    return scene, (a, sim.snapshot())


def bench_render(quick: bool = False, sheets: tuple = SHEETS) -> list[dict]:
    """ms per frame for each sheet × image size: the median over timed blocks after a
    warm-up, with the fastest and slowest block as the spread."""
    from ..render.renderer import Renderer

    blocks, per_block = (3, 5) if quick else (7, 10)
    rows = []
    for n in sheets:
        scene, snaps = _snapshots(n)
        renderer = Renderer(scene, SIZES[0])
        try:
            for w, h in SIZES:
                renderer.resize(w, h)
                for k in range(3):  # warm-up: shader compilation, buffer allocation
                    renderer.render(snaps[k % 2])
                times = []
                for _ in range(blocks):
                    t0 = time.perf_counter()
                    for k in range(per_block):
                        renderer.render(snaps[k % 2])
                    times.append((time.perf_counter() - t0) * 1e3 / per_block)
                rows.append({
                    "bench": "render",
                    "resolution": n,
                    "particles": n * n,
                    "size": f"{w}x{h}",
                    "ms_per_frame": round(statistics.median(times), 3),
                    "ms_min": round(min(times), 3),
                    "ms_max": round(max(times), 3),
                    "blocks": blocks,
                    "frames_per_block": per_block,
                })
        finally:
            renderer.close()
    return rows


def format_rows(rows: list[dict]) -> str:
    lines = [f"{'sheet':>9} {'image':>9} {'ms/frame':>9} {'min':>7} {'max':>7}"]
    for r in rows:
        lines.append(f"{r['resolution']:>4}x{r['resolution']:<4} {r['size']:>9} "
                     f"{r['ms_per_frame']:>9.2f} {r['ms_min']:>7.2f} {r['ms_max']:>7.2f}")
    return "\n".join(lines)


if __name__ == "__main__":
    import sys
    print(format_rows(bench_render(quick="--quick" in sys.argv)))


