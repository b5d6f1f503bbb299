"""The status line: rates, step cost, stretch and energy, the stretch tolerance and what it
costs, a sparkline of ms per frame and the recording mark. `Readout` is plain Python (no
Textual) so the numbers are testable alone."""

from __future__ import annotations

import math
import time
from collections import deque

from textual.app import ComposeResult
from textual.containers import Horizontal, Vertical
from textual.content import Content
from textual.widgets import Sparkline, Static

# An xpbd residual (m) below this is not worth a place on the status line.
CONSTRAINT_ERROR_SHOWN = 1e-4


class RateMeter:
    """Events per second over a sliding window, from (time, running count) samples."""

    def __init__(self, window: float = 1.0):
        self.window = window
        self._samples: deque[tuple[float, float]] = deque()

    def add(self, count: float, now: float | None = None) -> None:
        now = time.perf_counter() if now is None else now
        if self._samples and count < self._samples[-1][1]:
            self._samples.clear()  # the counter restarted
        self._samples.append((now, count))
        while len(self._samples) > 2 and now - self._samples[1][0] > self.window:
            self._samples.popleft()

    def rate(self, now: float | None = None) -> float:
        if len(self._samples) < 2:
            return 0.0
        now = time.perf_counter() if now is None else now
        (t0, c0), (t1, c1) = self._samples[0], self._samples[-1]
        if now - t1 > self.window:  # nothing new for a while: stopped
            return 0.0
        return (c1 - c0) / (t1 - t0) if t1 > t0 else 0.0


class Readout:
    """What the status line shows, updated from snapshots and frames."""

    def __init__(self, history: int = 80):
        self.sim_rate = RateMeter()
        self.view_rate = RateMeter()
        self.shown = 0
        self.stats: dict = {}
        self.frame_ms = 0.0
        self.step_ms = 0.0
        self.render_ms = 0.0
        self.energy0: float | None = None
        self.ms_history: deque[float] = deque([0.0] * history, maxlen=history)
        self.last_frame = -1
        self.graphics = ""  # how the preview draws: 'kitty', 'sixel', 'blocks 256'…

    def restart(self) -> None:
        self.energy0 = None

    def on_snapshot(self, frame: int, stats: dict) -> None:
        if frame < self.last_frame or self.energy0 is None:
            self.energy0 = stats.get("energy")
        if frame != self.last_frame:
            self.frame_ms = stats.get("frame_ms", 0.0)
            self.step_ms = stats.get("step_ms", 0.0)
            self.ms_history.append(self.frame_ms)
        self.last_frame = frame
        self.stats = stats
        self.sim_rate.add(frame)

    def on_frame(self, render_ms: float) -> None:
        self.shown += 1
        self.render_ms = render_ms
        self.view_rate.add(self.shown)

    @property
    def drift(self) -> float:
        e = self.stats.get("energy")
        if e is None or self.energy0 is None:
            return 0.0
        return e - self.energy0

    def tolerance_text(self) -> str:
        """"tol 5 % → 12 substeps, 3.1 ms/frame": what the tolerance costs, and a warning
        when the frame did not meet it (the substeps at their cap, or springs, whose stretch
        is their stiffness's)."""
        s = self.stats
        tol = s.get("stretch_tolerance")
        if tol is None:
            return ""
        text = (f"tol {100 * tol:g} % → {s.get('substeps_used', 0)} substeps, "
                f"{self.frame_ms:.1f} ms/frame")
        if s.get("tolerance_met", True):
            return f"[b]{text}[/]"
        return f"[b black on yellow] {text}: NOT MET [/]"

    def text(self, *, paused: bool, recording: bool, iterations: int,
             substeps: int, compact: bool = False) -> tuple[str, str]:
        """(state line, cost line): what the sim and view do, and what a frame costs.
        `compact` (a narrow terminal): rates, stretch and energy fit in 78 columns."""
        s = self.stats
        pct = lambda x: "—" if x is None or not math.isfinite(x) else f"{100 * x:.2f}%"  # noqa
        if compact:
            return self._compact_text(recording, paused, iterations, substeps)
        parts = ["[b white on red] ● REC [/]"] if recording else []
        parts += [
            "[b yellow]⏸ PAUSED[/]" if paused else "[b green]▶ running[/]",
            f"sim {self.sim_rate.rate():3.0f} fps",
            f"view {self.view_rate.rate():3.0f} fps"
            + (f" ({self.graphics})" if self.graphics else ""),
            f"{s.get('particles', 0)} particles",
            f"stretch max [b]{pct(s.get('max_stretch'))}[/] mean {pct(s.get('mean_stretch'))}",
            f"E {s.get('energy', 0.0):+.3f} J  ΔE since restart {self.drift:+.3f} J",
        ]
        if s.get("torn"):
            parts.append(f"[b]{s['torn']} torn[/]")
        residual = s.get("constraint_error")
        if residual is not None and residual > CONSTRAINT_ERROR_SHOWN:
            parts.append(f"constraint error {1e3 * residual:.2f} mm")
        if s.get("halted"):
            parts.append("[b white on red] HALTED: diverging [/]")
        if s.get("recoveries"):
            parts.append(f"[red]{s['recoveries']} recoveries[/]")
        used = s.get("substeps_used", substeps)
        shown = f"{substeps}" if used == substeps else f"{substeps} (now {used})"
        frame = self.tolerance_text() or f"cost [b]{self.frame_ms:6.2f}[/] ms/frame"
        cost = (f"{frame}, {self.step_ms:5.3f} ms/step at "
                f"{iterations} iterations × {shown} substeps · render {self.render_ms:5.1f} ms"
                f" · ms/frame:")
        return " · ".join(parts), cost


    def _compact_text(self, recording: bool, paused: bool, iterations: int,
                      substeps: int) -> tuple[str, str]:
        s = self.stats
        parts = ["[b white on red]● REC[/]"] if recording else []
        pct = lambda x: "—" if x is None or not math.isfinite(x) else f"{100 * x:.2f}%"  # noqa
        state = ("[b yellow]⏸ PAUSED[/]", "[b green]▶ running[/]")
        if parts:  # recording: the mark takes the state word's room
            state = ("[b yellow]⏸[/]", "[b green]▶[/]")
        parts += [
            state[0] if paused else state[1],
            f"sim {self.sim_rate.rate():.0f} fps",
            f"view {self.view_rate.rate():.0f} fps",
            f"stretch [b]{pct(s.get('max_stretch'))}[/]",
            f"E {s.get('energy', 0.0):+.4g} J ΔE {self.drift:+.4g} J",  # 4 digits fit
        ]
        if s.get("halted"):
            parts.insert(0, "[b white on red] HALTED [/]")
        used = s.get("substeps_used", substeps)
        cost = (f"{self.frame_ms:.1f} ms/frame · {self.step_ms:.3f} ms/step · "
                f"{iterations}×{used} · render {self.render_ms:.1f} ms")
        return " · ".join(parts), cost


class StatusBar(Vertical):
    DEFAULT_CSS = """
    StatusBar { height: 2; }
    StatusBar #status-text { width: 1fr; height: 1; }
    StatusBar #cost-row { height: 1; }
    StatusBar #cost-text { width: auto; height: 1; }
    StatusBar Sparkline { width: 1fr; height: 1; margin-left: 1; }
    """

    def compose(self) -> ComposeResult:
        self._cost_width = 0
        self._text = Static("starting…", id="status-text")
        self._cost = Static("", id="cost-text")
        self._spark = Sparkline([0.0], id="ms-spark", summary_function=max)
        self._spark.tooltip = "simulation ms per frame, last 80 frames (a bar: its worst)"
        yield self._text
        with Horizontal(id="cost-row"):
            yield self._cost
            yield self._spark

    def show(self, text: tuple[str, str], history) -> None:
        # A layout pass of the whole screen held the UI thread ~14 ms (and with it the GIL the
        # simulation thread needs between kernels) five times a second: only the cost text's
        # width can move the layout, so only a change of its width asks for one.
        self._text.update(text[0], layout=False)
        width = Content.from_markup(text[1]).cell_length
        self._cost.update(text[1], layout=width != self._cost_width)
        self._cost_width = width
        self._spark.data = list(history)
