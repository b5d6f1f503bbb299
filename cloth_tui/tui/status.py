"""The status line: rates, step cost, stretch and energy, the material, the error tolerance and what
it costs, the numerical damping, a sparkline of ms per frame and the recording mark. `Readout` is
plain Python (no Textual) so the numbers are testable alone."""

from __future__ import annotations

import math
import time
from collections import deque
from typing import NamedTuple

from rich.text import Text

from textual.app import ComposeResult
from textual.containers import Horizontal, Vertical
from textual.content import Content
from textual.widgets import Sparkline, Static

from ..sim.run.run_stats import RunStats

# Numerical damping (share of free energy per second) below this is not worth a place.
DAMPING_SHOWN = 1e-3
WIDE_TEXT = 1000      # cells: a line with room for everything in its longest form
SPARK_AT_LEAST = 12   # cells the cost line leaves for the sparkline of ms per frame


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
        self.stats = RunStats()
        self.frame_ms = 0.0
        self.step_ms = 0.0
        self.render_ms = 0.0
        self.energy0: float | None = None
        self.ms_history: deque[float] = deque([0.0] * history, maxlen=history)
        self.last_frame = -1
        self.graphics = ""  # how the preview draws: 'kitty', 'sixel', 'blocks 256'…
        self.compiling = ""  # "compiling kernels (first run only)… 3 compiled, 9 s", or ""

    def restart(self) -> None:
        self.energy0 = None

    def on_snapshot(self, frame: int, stats: RunStats) -> None:
        if frame < self.last_frame or self.energy0 is None:
            self.energy0 = stats.energy
        if frame != self.last_frame:
            self.frame_ms = stats.frame_ms
            self.step_ms = stats.step_ms
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
        e = self.stats.energy
        if e is None or self.energy0 is None:
            return 0.0
        return e - self.energy0

    def tolerance_text(self, short: bool = False, compact: bool = False) -> str:
        """"denim · error 0.5 % → 9 substeps, 4.1 ms/frame": the material (or, without one,
        the solver), the error tolerance (and the energy tolerance, if set), what they cost,
        and a warning when the frame did not meet them (the substeps at their cap, or
        springs). `short`: "NOT MET" without its padding and colon; `compact` also
        abbreviates ("denim · err 0.5 % → 9 sub, 4.1 ms")."""
        s = self.stats
        tol = s.error_tolerance
        if tol is None:
            return ""
        what = s.material or s.solver
        bound = f"{'err' if compact else 'error'} {100 * tol:g} %"
        if s.energy_tolerance:
            bound += f", {'damp' if compact else 'damping'} {100 * s.energy_tolerance:g} %/s"
        used = s.substeps_used
        text = (f"{what + ' · ' if what else ''}{bound} → "
                + (f"{used} sub, {self.frame_ms:.1f} ms" if compact else
                   f"{used} substep{'' if used == 1 else 's'}, {self.frame_ms:.1f} ms/frame"))
        if s.tolerance_met is not False:
            return f"[b]{text}[/]"
        if short or compact:
            return f"[b black on yellow]{text} NOT MET[/]"
        return f"[b black on yellow] {text}: NOT MET [/]"

    def text(self, *, paused: bool, recording: bool, iterations: int,
             substeps: int, width: int = WIDE_TEXT) -> tuple[str, str]:
        """(state line, cost line) for a status line `width` cells wide: what the sim and
        view do, and what a frame costs (the cost line leaves room for the sparkline).

        Every width keeps the state, both rates and how the preview draws, the particle
        count, the largest stretch, ΔE with its unit, the tolerance's cost, the numerical
        damping, and any tear, halt or recovery. What gives way, first to last:
        the words around the energy (E, "since restart"), the mean stretch, the step's
        breakdown, the render time, the rates' padding and "running"/"paused". Where the
        state line does not fit even so (below ~110 cells), the particle count and the
        marks (tears, the numerical damping, recoveries) move to the cost line."""
        wide = self._lines(paused, recording, iterations, substeps, width, narrow=False)
        if cells(wide[0]) <= width:
            return wide
        return self._lines(paused, recording, iterations, substeps, width, narrow=True)

    def _lines(self, paused: bool, recording: bool, iterations: int, substeps: int,
               width: int, narrow: bool) -> tuple[str, str]:
        s = self.stats
        pct = lambda x: "—" if x is None or not math.isfinite(x) else f"{100 * x:.2f}%"  # noqa
        state = ([Part(("[b white on red] ● REC [/]", "[b white on red]● REC[/]",
                        "[b white on red]●[/]"), 8)] if recording else [])
        if s.halted:
            state.insert(0, Part(("[b white on red] HALTED: diverging [/]",
                                  "[b white on red] HALTED [/]"), 8))
        sim, view = self.sim_rate.rate(), self.view_rate.rate()
        mode = f" ({self.graphics})" if self.graphics else ""
        if self.compiling:  # a first run: the sim stands still for a minute, and says why
            brief = self.compiling.replace(" (first run only)", "")
            run = Part((f"[b yellow]{self.compiling}[/]", f"[b yellow]{brief}[/]",
                        "[b yellow]compiling…[/]"), 9)
        elif paused:
            run = Part(("[b yellow]⏸ PAUSED[/]", "[b yellow]⏸[/]"), 3)
        else:
            run = Part(("[b green]▶ running[/]", "[b green]▶[/]"), 3)
        state += [
            run,
            # No simulated frame comes while the first kernels compile: no rate to show.
            Part(("",) if self.compiling else (f"sim {sim:3.0f} fps", f"sim {sim:.0f} fps"), 4),
            Part((f"view {view:3.0f} fps{mode}", f"view {view:.0f} fps{mode}"), 4),
        ]
        particles = Part((f"{s.particles} particles",), 9)
        stretch = Part((f"stretch max [b]{pct(s.max_stretch)}[/] mean "
                        f"{pct(s.mean_stretch)}",
                        f"stretch max [b]{pct(s.max_stretch)}[/]",
                        f"stretch [b]{pct(s.max_stretch)}[/]"), 1)
        e, de = s.energy or 0.0, self.drift
        energy = Part((f"E {e:+.3f} J  ΔE since restart {de:+.3f} J", f"E {e:+.4g} J ΔE "
                       f"{de:+.4g} J", f"ΔE {de:+.4g} J"), 0)
        marks = []  # tears, the numerical damping, recoveries: shown at every width
        if s.torn:
            marks.append(Part((f"[b]{s.torn} torn[/]",), 9))
        damping = s.numerical_damping
        if damping is not None and abs(damping) > DAMPING_SHOWN:
            marks.append(Part((f"numerical damping {100 * damping:.1f} %/s",
                               f"num. damping {100 * damping:.1f} %/s",
                               f"damping {100 * damping:.1f} %/s"), 5))
        if s.recoveries:
            marks.append(Part((f"[red]{s.recoveries} recoveries[/]",), 9))

        used = s.substeps_used or substeps
        shown = f"{substeps}" if used == substeps else f"{substeps} (now {used})"
        frame = self.tolerance_text()
        fabric = f"{s.material} · " if s.material else ""  # named without a tolerance too
        frame_part = Part((frame, self.tolerance_text(short=True),
                           self.tolerance_text(compact=True)), 6) if frame else \
            Part((f"{fabric}cost [b]{self.frame_ms:6.2f}[/] ms/frame",
                  f"{fabric}{self.frame_ms:.1f} ms/frame"), 6)
        cost = [frame_part,
                Part((f"{self.step_ms:5.3f} ms/step at {iterations} iterations × {shown} "
                      f"substeps", f"{self.step_ms:.3f} ms/step · {iterations}×{used}",
                      f"{iterations}×{used}", ""), 2),
                Part((f"render {self.render_ms:5.1f} ms", f"render {self.render_ms:.0f} ms", ""),
                     1)]
        if narrow:
            state += [stretch, energy]
            cost = [particles, cost[0], *marks, *cost[1:]]
        else:
            state += [particles, stretch, energy, *marks]
            cost.append(Part(("ms/frame:", ""), 0))
        return fit(state, width), fit(cost, width - (0 if narrow else SPARK_AT_LEAST))


class Part(NamedTuple):
    """One item of a status line: its forms, longest first ("" drops it), and its rank:
    of the items that can still shorten, those shortened least do first, and of those
    the lowest-ranked."""
    forms: tuple[str, ...]
    rank: int


def cells(markup: str) -> int:
    return Text.from_markup(markup).cell_len


def fit(parts: list[Part], width: int, sep: str = " · ") -> str:
    """The parts joined, each in the longest form that lets the line fit `width` cells,
    shortening them in Part's order; as short as they go if even that does not fit."""
    chosen = [0] * len(parts)

    def line() -> str:
        return sep.join(f for p, i in zip(parts, chosen) if (f := p.forms[i]))

    text = line()
    while cells(text) > width:
        can = [k for k, p in enumerate(parts) if chosen[k] + 1 < len(p.forms)]
        if not can:
            break
        k = min(can, key=lambda k: (chosen[k], parts[k].rank, k))  # first steps first
        chosen[k] += 1
        text = line()
    return text


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
        # A layout pass of the whole screen holds the UI thread (and with it the GIL the
        # simulation thread needs between kernels) for milliseconds: only the cost text's
        # width can move the layout, so only a change of its width asks for one.
        self._text.update(text[0], layout=False)
        width = Content.from_markup(text[1]).cell_length
        self._cost.update(text[1], layout=width != self._cost_width)
        self._cost_width = width
        self._spark.data = list(history)
