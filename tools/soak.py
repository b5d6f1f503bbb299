"""Soak the real app: `cloth-tui` in a pseudo-terminal (the real Textual driver and output,
the real renderer), auto-rotating the whole time and recording a video part of the time.
Prints the resident memory (RSS) at the start, after the warm-up and at the end, and the
simulated and shown frame rates of the measured part.

    python tools/soak.py --seconds 600            # the 10-minute run of docs/app.md
    python tools/soak.py --seconds 50 --warmup 20 --record 1 --json  # the default test run
    python tools/soak.py --seconds 85 --warmup 25 --json  # its slow form

The warm-up (`--warmup`, part of `--seconds`) records a short video once, so buffers of the
video's picture size exist before the measurement starts. Rates come from the app's debug
log (CLOTH_TUI_DEBUG_LOG): one line per shown frame naming the simulation frame it shows.
Linux only (RSS from /proc). Exit status: 0 measured, 1 the app did not run (no frame shown
or it died), 2 bad arguments.
"""

from __future__ import annotations

import argparse
import fcntl
import json
import os
import struct
import subprocess
import sys
import tempfile
import termios
import threading
import time
from dataclasses import asdict, dataclass
from pathlib import Path

FIRST_FRAME_TIMEOUT_S = 90.0  # start-up, plus compiling the kernels on a cold cache
QUIT_TIMEOUT_S = 20.0


@dataclass
class SoakResult:
    seconds: float            # measured span (after the warm-up)
    rss_start_mb: float       # at the first shown frame
    rss_warm_mb: float        # after the warm-up
    rss_end_mb: float         # at the end, before quitting
    growth_mb: float          # end − after warm-up
    slope_mb_per_s: float     # least-squares slope of the samples after the warm-up
    sim_fps: float            # simulation frames per second, measured span
    shown_fps: float          # frames shown per second, measured span
    frames_shown: int         # in the measured span
    videos: int               # finished videos in the captures folder
    exit_code: int | None     # the app's, after `q`


def rss_mb(pid: int) -> float:
    with open(f"/proc/{pid}/status") as fh:
        for line in fh:
            if line.startswith("VmRSS:"):
                return int(line.split()[1]) / 1024.0
    raise RuntimeError(f"no VmRSS for process {pid}")


def slope(samples: list[tuple[float, float]]) -> float:
    """Least-squares slope of (t, value) samples."""
    if len(samples) < 2:
        return 0.0
    n = len(samples)
    mt = sum(t for t, _ in samples) / n
    mv = sum(v for _, v in samples) / n
    den = sum((t - mt) ** 2 for t, _ in samples)
    return sum((t - mt) * (v - mv) for t, v in samples) / den if den else 0.0


def shown_frames(log: Path) -> list[tuple[float, int]]:
    """(perf_counter time, simulation frame) of every frame the app showed."""
    out = []
    for line in log.read_text(encoding="utf-8").splitlines():
        parts = line.split()
        if len(parts) >= 3 and parts[1] == "frame":
            out.append((float(parts[0]), int(parts[2])))
    return out


class TerminalApp:
    """`python -m cloth_tui ARGS` on a pseudo-terminal of a given size; its output is read
    and dropped (a terminal that is never read would block the app)."""

    def __init__(self, args: list[str], cols: int, rows: int, env: dict[str, str]):
        master, slave = os.openpty()
        fcntl.ioctl(slave, termios.TIOCSWINSZ, struct.pack("HHHH", rows, cols, 0, 0))
        self.proc = subprocess.Popen([sys.executable, "-m", "cloth_tui", *args],
                                     stdin=slave, stdout=slave, stderr=slave, env=env,
                                     start_new_session=True, close_fds=True)
        os.close(slave)
        self._master = master
        self.output_bytes = 0
        self._reader = threading.Thread(target=self._drain, daemon=True)
        self._reader.start()

    def _drain(self) -> None:
        while True:
            try:
                data = os.read(self._master, 1 << 16)
            except OSError:  # EIO: the app closed the terminal
                return
            if not data:
                return
            self.output_bytes += len(data)

    def press(self, key: str) -> None:
        os.write(self._master, key.encode())

    def quit(self) -> int | None:
        if self.proc.poll() is None:
            self.press("q")
            try:
                self.proc.wait(QUIT_TIMEOUT_S)
            except subprocess.TimeoutExpired:
                self.proc.kill()
                self.proc.wait()
        os.close(self._master)
        return self.proc.returncode


def soak(seconds: float, warmup: float, scene: str, size: tuple[int, int],
         record_fraction: float, captures: Path, verbose: bool = False) -> SoakResult:
    log = captures / "debug.log"
    env = dict(os.environ, CLOTH_TUI_DEBUG_LOG=str(log), TERM="xterm-256color",
               COLORTERM="truecolor")
    app = TerminalApp([scene, "--set", "appearance.auto_rotate=true",
                       "--captures", str(captures)], *size, env=env)
    try:
        deadline = time.monotonic() + FIRST_FRAME_TIMEOUT_S
        while not (log.exists() and shown_frames(log)):
            if app.proc.poll() is not None:
                raise RuntimeError(f"the app exited with status {app.proc.returncode} "
                                   "before showing a frame")
            if time.monotonic() > deadline:
                raise RuntimeError(f"no frame shown within {FIRST_FRAME_TIMEOUT_S:.0f} s "
                                   "(is a renderer available?)")
            time.sleep(0.2)
        pid = app.proc.pid
        t0 = time.monotonic()
        rss_start = rss_mb(pid)

        def wait_until(t: float) -> None:
            while time.monotonic() < t0 + t:
                if app.proc.poll() is not None:
                    raise RuntimeError(f"the app died with status {app.proc.returncode}")
                time.sleep(0.1)

        # Warm-up: one short recording, so the video-sized buffers exist before measuring.
        wait_until(0.3 * warmup)
        app.press("v")
        wait_until(0.6 * warmup)
        app.press("v")
        span = seconds - warmup
        if record_fraction == 1.0:
            # Recording the whole span: its video starts inside the warm-up, so the one-off
            # step in RSS a recording's start makes is not counted as growth.
            record_from, record_to = 0.8 * warmup, seconds + 1.0
        else:
            record_from = warmup + span * (1 - record_fraction) / 2
            record_to = record_from + span * record_fraction
        recording = False
        if record_from < warmup:
            wait_until(record_from)
            app.press("v")
            recording = True
        wait_until(warmup)
        rss_warm = rss_mb(pid)
        pc_warm = time.perf_counter()  # CLOCK_MONOTONIC on Linux, as the app's log times
        samples = [(time.monotonic(), rss_warm)]
        while time.monotonic() < t0 + seconds:
            wait_until(min(seconds, time.monotonic() - t0 + 1.0))
            elapsed = time.monotonic() - t0
            if (record_from <= elapsed < record_to) != recording:
                app.press("v")
                recording = not recording
            samples.append((time.monotonic(), rss_mb(pid)))
            if verbose:
                print(f"{elapsed:6.1f} s  RSS {samples[-1][1]:7.1f} MB"
                      + ("  recording" if recording else ""), file=sys.stderr)
        if recording:
            app.press("v")
            time.sleep(1.0)  # the video's last fragment is written
        rss_end = rss_mb(pid)
        pc_end = time.perf_counter()
    finally:
        exit_code = app.quit()
    frames = [(t, f) for t, f in shown_frames(log) if pc_warm <= t <= pc_end]
    dt = frames[-1][0] - frames[0][0] if len(frames) > 1 else 0.0
    return SoakResult(
        seconds=round(pc_end - pc_warm, 1), rss_start_mb=round(rss_start, 1),
        rss_warm_mb=round(rss_warm, 1), rss_end_mb=round(rss_end, 1),
        growth_mb=round(rss_end - rss_warm, 2), slope_mb_per_s=round(slope(samples), 4),
        sim_fps=round((frames[-1][1] - frames[0][1]) / dt, 1) if dt else 0.0,
        shown_fps=round((len(frames) - 1) / dt, 1) if dt else 0.0,
        frames_shown=len(frames), videos=len(list(captures.glob("*.mp4"))),
        exit_code=exit_code)


def main(argv: list[str] | None = None) -> int:
    p = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    p.add_argument("--seconds", type=float, default=600.0,
                   help="running time after the first frame, warm-up included (default 600)")
    p.add_argument("--warmup", type=float, default=15.0, help="warm-up seconds (default 15)")
    p.add_argument("--scene", default="default")
    p.add_argument("--size", default="160x48", help="terminal COLSxROWS (default 160x48)")
    p.add_argument("--record", type=float, default=0.3, dest="record_fraction",
                   help="fraction of the measured span spent recording, in its middle "
                   "(default 0.3); 1 records it all, the video started inside the warm-up")
    p.add_argument("--captures", type=Path, help="folder for the video and the debug log "
                   "(default: a temporary folder, removed afterwards)")
    p.add_argument("--json", action="store_true", help="print one JSON object")
    p.add_argument("--verbose", action="store_true", help="print RSS every second (stderr)")
    a = p.parse_args(argv)
    try:
        cols, rows = (int(v) for v in a.size.lower().split("x"))
    except ValueError:
        print(f"soak: error: --size {a.size!r} is not COLSxROWS", file=sys.stderr)
        return 2
    if not 0 < a.warmup < a.seconds or not 0 <= a.record_fraction <= 1:
        print("soak: error: need 0 < --warmup < --seconds and 0 ≤ --record ≤ 1",
              file=sys.stderr)
        return 2
    with tempfile.TemporaryDirectory(prefix="cloth-soak-") as tmp:
        captures = a.captures or Path(tmp)
        captures.mkdir(parents=True, exist_ok=True)
        try:
            r = soak(a.seconds, a.warmup, a.scene, (cols, rows), a.record_fraction, captures,
                     a.verbose)
        except RuntimeError as e:
            print(f"soak: error: {e}", file=sys.stderr)
            return 1
    if a.json:
        print(json.dumps(asdict(r)))
    else:
        print(f"RSS start {r.rss_start_mb:.1f} MB, after {a.warmup:.0f} s warm-up "
              f"{r.rss_warm_mb:.1f} MB, end {r.rss_end_mb:.1f} MB: grew {r.growth_mb:+.2f} MB "
              f"in {r.seconds:.0f} s (slope {r.slope_mb_per_s:+.4f} MB/s)")
        print(f"simulated {r.sim_fps:.1f} fps, shown {r.shown_fps:.1f} fps "
              f"({r.frames_shown} frames), videos {r.videos}, app exit {r.exit_code}")
    return 0


if __name__ == "__main__":
    raise SystemExit(main())
