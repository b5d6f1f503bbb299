"""`cloth-tui wedge SCENE --vary KEY=V1,V2,… [--vary …] -o SHEET.png|SHEET.mp4 …`: every
combination as a task on Dask, then the contact sheet (atomically written, partial after
Ctrl+C) and a table or `--json` of each run's measures."""

from __future__ import annotations

import json
import math
import sys
import time
from pathlib import Path

from ..interrupt import EXIT_BY_SIGNAL, Interrupt, Progress
from ..safe_text import escape_controls
from ..scene_files import apply_overrides, load
from ..usage import UsageError, check_output_path
from .engine import Engine, Failed, require_dask, worker_count
from .plan import plan, value_text

VIDEO_FPS = 30
# Every clip comes back to this process before the grid is encoded: bound what that holds.
VIDEO_MAX_BYTES = 1 << 30
MEASURES = ("max_stretch", "energy_drift", "penetration", "recoveries", "substeps_used",
            "halted", "finite", "wall_s", "task_s", "worker")


def _num(v):
    """JSON has no NaN/inf: null instead."""
    return None if isinstance(v, float) and not math.isfinite(v) else v


def run_record(cell, result) -> dict:
    status = ("done" if isinstance(result, dict) else
              "failed" if isinstance(result, Failed) else "cancelled")
    out = {"values": cell.values, "status": status}
    if isinstance(result, dict):
        out |= {k: _num(result[k]) for k in MEASURES}
    elif isinstance(result, Failed):
        out["error"] = result.reason
    return out


def format_table(records: list[dict], keys: list[str]) -> str:
    head = [k.split(".", 1)[1] for k in keys] + ["stretch %", "ΔE J", "pen. mm", "recov.",
                                                 "substeps", "wall s", "status"]
    rows = []
    for r in records:
        vals = [value_text(r["values"][k]) for k in keys]
        if r["status"] == "done":
            vals += [f"{100 * r['max_stretch']:.2f}" if r["max_stretch"] is not None else "—",
                     f"{r['energy_drift']:+.4g}" if r["energy_drift"] is not None else "—",
                     f"{1e3 * r['penetration']:.2f}", str(r["recoveries"]),
                     str(r["substeps_used"]), f"{r['wall_s']:.3f}",
                     "halted" if r["halted"] else "ok"]
        else:
            vals += ["—"] * 6 + [r["status"]]
        rows.append(vals)
    widths = [max(len(h), *(len(row[i]) for row in rows)) for i, h in enumerate(head)]
    line = lambda cells: "  ".join(c.rjust(w) for c, w in zip(cells, widths))  # noqa: E731
    return "\n".join([line(head)] + [line(r) for r in rows])


def _check_output(out: Path, video: bool) -> None:
    if video and out.suffix.lower() != ".mp4":
        raise UsageError(f"{out}: with --video the sheet is an MP4 grid; use a .mp4 file name")
    if not video and out.suffix.lower() != ".png":
        raise UsageError(f"{out}: the sheet is a PNG (an MP4 grid with --video); "
                         "use a .png file name")
    check_output_path(out, (".mp4",) if video else (".png",))


def write_sheet(out: Path, varies, cells, results, thumb, frames: int, scene_name: str,
                video: bool) -> None:
    from ..render.capture import VideoWriter, save_png
    from .sheet import VIDEO_BLOCK, clip_frames, layout_sheet, still, title_of

    title = title_of(scene_name, frames, varies)
    sheet = layout_sheet(varies, cells, results, thumb, title, VIDEO_BLOCK if video else 1)
    if not video:
        save_png(still(sheet, results), out)
        return
    h, w = sheet.background.shape[:2]
    writer = VideoWriter(out, VIDEO_FPS, (w, h))
    try:
        for image in clip_frames(sheet, results, frames):
            writer.write(image)
        writer.close()
    except BaseException:
        writer.discard()
        raise


def check_runs(cells, progress: Progress) -> None:
    """Refuse, before any worker starts, a combination `simulate` would refuse: each cell's
    Simulation is built here (the sheet, its pins, its colliders, the held particles'
    checks) and dropped, nothing stepped. The plan checked each scene's keys; what only the
    simulation's set-up finds (an object enclosing a held particle, say) would otherwise
    fail on a worker, after the cluster started, as a failed run and exit 1."""
    from ..scene import SceneError
    from ..sim.run.runner import Simulation

    progress.show(0)
    for done, cell in enumerate(cells, 1):
        try:
            Simulation(cell.scene)
        except SceneError as e:
            progress.end()
            shown = ", ".join(f"{k}={value_text(x)}" for k, x in cell.values.items())
            raise UsageError(f"--vary: the run {shown} is refused: {e}") from None
        progress.show(done)
    progress.end()


def run_wedge(args) -> int:
    from ..render.cli import default_frames, parse_size

    out = Path(args.output)
    _check_output(out, args.video)
    thumb = parse_size(args.size)
    base = apply_overrides(load(args.scene), args.overrides)
    varies, cells = plan(base, args.vary)
    frames = args.frames or default_frames(".mp4" if args.video else ".png", base)
    if args.video and len(cells) * frames * thumb[0] * thumb[1] * 3 > VIDEO_MAX_BYTES:
        raise UsageError(f"--video: {len(cells)} clips of {frames} frames at {thumb[0]}x"
                         f"{thumb[1]} exceed {VIDEO_MAX_BYTES >> 20} MB held in memory; use "
                         "fewer runs or --frames, or a smaller --size")
    check_runs(cells, Progress(len(cells), sys.stderr.isatty(), "checking runs"))
    require_dask()
    if not args.scheduler:  # local workers draw with this machine's GL: say now if it has none
        from ..render.probe import RendererUnavailable, require_renderer
        try:
            require_renderer()
        except RendererUnavailable as e:
            print(escape_controls(f"cloth-tui: error: {e}"), file=sys.stderr)
            return 1
    from .task import run_cell

    workers = worker_count(args.workers, len(cells))
    progress = Progress(len(cells), sys.stderr.isatty(), "wedge")
    finished = []

    def on_done(i, result):
        finished.append(i)
        progress.show(len(finished))

    started = time.perf_counter()
    with Interrupt() as interrupt:
        progress.show(0)
        with Engine(workers, args.scheduler, stop=lambda: interrupt.signum is not None) \
                as engine:
            startup = time.perf_counter() - started
            results = engine.run(run_cell, [(c.scene, frames, thumb, args.video) for c in cells],
                                 on_done, stop=lambda: interrupt.signum is not None)
            elapsed = time.perf_counter() - started  # to the last result, with the start-up
        progress.end()
        from ..render.capture import CaptureError
        try:
            write_sheet(out, varies, cells, results, thumb, frames, base.name, args.video)
            sheet_error = None
        except CaptureError as e:  # the disk filled up meanwhile, say: the table still shows
            sheet_error = str(e)
    records = [run_record(c, r) for c, r in zip(cells, results)]
    done = sum(r["status"] == "done" for r in records)
    failed = [r for r in records if r["status"] == "failed"]
    if args.json:
        print(json.dumps({"scene": base.name, "frames": frames,
                          "vary": {v.key: list(v.values) for v in varies},
                          "sheet": None if sheet_error else str(out),
                          "complete": done == len(cells), "workers": args.scheduler or workers,
                          "elapsed_s": elapsed, "startup_s": startup, "runs": records}))
    else:
        print(format_table(records, [v.key for v in varies]))
        print(f"\n{done} of {len(cells)} runs in {elapsed:.1f} s ({startup:.1f} s of it starting "
              f"the cluster); " + ("no contact sheet" if sheet_error else
                                    f"contact sheet written to {out}"))
    if sheet_error is not None:  # the sheet cannot be written (a full disk): exit 2, as render
        print(escape_controls(f"cloth-tui: error: {sheet_error}"), file=sys.stderr)
        return 2
    if interrupt.signum is not None:
        print(escape_controls(f"cloth-tui: {interrupt.name}: stopped after {done} of "
                              f"{len(cells)} runs; {'partial ' if done < len(cells) else ''}"
                              f"sheet written to {out}"),
              file=sys.stderr)
        return EXIT_BY_SIGNAL[interrupt.signum]
    if failed:
        print(escape_controls(f"cloth-tui: error: {len(failed)} of {len(cells)} runs failed; "
                              f"first: {failed[0]['error']}"), file=sys.stderr)
        return 1
    return 0
