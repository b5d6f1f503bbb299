"""`cloth-tui BAKE.usd(c/a)`: the app playing a bake instead of simulating. It is the live
app (the same preview, render service, captures and camera keys) with a `BakePlayer` in
place of the simulation thread and a `Timeline` in place of the control panels. Reading a
frame is cheap (one time sample of the points), so the player runs on the UI thread, on a
timer at the bake's frame rate, and hands each frame to the renderer as the simulation's
snapshots are handed."""

from __future__ import annotations

import time
from pathlib import Path

from rich.markup import escape
from textual.app import App, ComposeResult
from textual.containers import Horizontal
from textual.widgets import Footer

from ..io.bake_player import BakePlayer
from ..io.usd_read import UsdBake
from ..render.replay import bake_scene
from ..safe_text import escape_controls
from ..scene import Scene
from .app import ClothApp, run_app
from .bindings import APP_BINDINGS
from .preview import Preview
from .status import StatusBar
from .timeline import Timeline

# The live app's keys that mean something for a recording: no bumps, restarts or bakes.
REPLAY_ACTIONS = ("quit", "toggle", "screenshot", "video", "orbit", "zoom", "reset_camera")
REPLAY_BINDINGS = [b for b in APP_BINDINGS if b.action.split("(")[0] in REPLAY_ACTIONS]
# The playback timer ticks at the bake's rate up to this; the player skips frames to keep the
# motion's speed. (A timer at a bake's 10⁴ frames/s left no time for keys or SIGTERM.)
MAX_TICK_HZ = 60.0


class ReplayApp(ClothApp, inherit_bindings=False):
    TITLE = "cloth-tui replay"
    AUTO_FOCUS = "Timeline"  # its keys: space, arrows, Home, End
    COMMANDS = App.COMMANDS  # no scene commands: a bake's scene is fixed
    BINDINGS = App.BINDINGS + REPLAY_BINDINGS
    CSS = "#ms-spark { display: none; }"  # no simulation ms per frame to plot

    def __init__(self, scene: Scene, captures_dir: Path, *, bake: UsdBake, **kwargs) -> None:
        super().__init__(scene, captures_dir, **kwargs)
        self.player = BakePlayer(bake, scene)

    def compose(self) -> ComposeResult:
        with Horizontal(id="main"):
            yield self._make_preview()
        yield Timeline(self.player.count, id="timeline")
        yield StatusBar(id="status")
        yield Footer(compact=True)

    @property
    def timeline(self) -> Timeline:
        return self.query_one(Timeline)

    def _start_sim(self, paused: bool) -> None:
        """Called by on_mount in place of starting a simulation: start the playback."""
        if not paused:
            self.player.play(time.monotonic())
        self._show_frame()
        self.set_interval(1 / min(self.player.frame_rate, MAX_TICK_HZ), self._tick)

    def _tick(self) -> None:
        if self.player.advance(time.monotonic()):
            self._show_frame(status=False)  # the status line follows 5 times a second

    def _show_frame(self, status: bool = True) -> None:
        snap = self.player.snapshot()
        if self.renderer is not None:
            self.renderer.submit(snap)
        self.timeline.show(self.player.index)
        if status:
            self._refresh_status()

    # -- timeline -------------------------------------------------------------------------
    def on_timeline_seek(self, message: Timeline.Seek) -> None:
        self.player.seek(message.index, time.monotonic())
        self._show_frame()

    def on_timeline_step(self, message: Timeline.Step) -> None:
        self.player.step(message.delta, time.monotonic())
        self._show_frame()

    def on_timeline_play_pause(self, _: Timeline.PlayPause) -> None:
        self.action_pause()

    def action_pause(self) -> None:
        self.player.toggle(time.monotonic())
        self._show_frame()

    # -- the live app's parts that have no counterpart here ------------------------------
    def apply_scene(self, new: Scene, *, restart: bool = False, shown: bool = False) -> None:
        """Only appearance changes (w, a): drawn again, nothing simulated."""
        self.scene = new
        if self.renderer is not None:
            self.renderer.update_scene(new)

    def _show_value(self, dotted: str) -> None:
        pass  # a replay has no panels: its keys' changes show in the picture alone

    def on_preview_grab(self, message: Preview.Grab) -> None:
        pass  # a recording cannot be pushed

    def _make_preview(self) -> Preview:
        preview = super()._make_preview()
        preview.show_crosshair = False  # it only aims bumps
        return preview

    def _place_crosshair(self) -> bool:
        return True  # none to place

    def _refresh_status(self) -> None:
        p = self.player
        recording = bool(self.renderer is not None and self.renderer.recording)
        parts = ["[b white on red] ● REC [/]"] if recording else []
        parts += [
            "[b green]▶ playing[/]" if p.playing else "[b yellow]⏸ paused[/]",
            f"frame [b]{p.index + 1}/{p.count}[/]",
            f"t {p.time:.3f} s",
            f"bake {p.frame_rate:g} fps",
            f"view {self.readout.view_rate.rate():3.0f} fps",
            f"{p.model.num_particles} particles",
        ]
        if self._no_preview is not None:
            parts.insert(0, "[b white on red] no preview [/]")
        name = escape(escape_controls(p.bake.path.name))
        cost = (f"replay of {name} · render {self.readout.render_ms:5.1f} ms · "
                f"space play/pause · ←→ step · Home/End · click or drag the timeline")
        for bar in self.query(StatusBar):  # none while the app is closing
            bar.show((" · ".join(parts), cost), [0.0])


def run_replay_app(path: Path, overrides: list[str], captures_dir: Path, **kwargs) -> int:
    """Open the bake (bad input, one line: no usd-core, not a bake, physics `--set`), then
    run the app on it."""
    bake = UsdBake(path)
    scene = bake_scene(bake, overrides)
    return run_app(scene, captures_dir, app_class=ReplayApp, bake=bake,
                   start_paused=False, **kwargs)
