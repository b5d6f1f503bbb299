"""The terminal app: a live preview, the control panels, a status line and the keys.

Threads: the simulation (`SimulationThread`) and the renderer (`RenderService`) run on their
own threads. They hand results to the UI through one-slot mailboxes and `post_message`
(thread-safe): a message is posted only when the previous one was consumed, so the UI never
queues stale frames, and it never waits on either thread.
"""

from __future__ import annotations

import os
import time
from collections import deque
from pathlib import Path
from typing import Any, Callable

from textual.app import App, ComposeResult
from textual.containers import Horizontal
from textual.screen import Screen
from textual.widgets import Footer, Input, OptionList

from ..compile_notice import CompileWatch
from ..newest_slot import NewestSlot
from ..render.service import Frame
from ..safe_text import escape_controls
from ..scene import Scene, SceneError
from ..scene_files import load
from ..sim.collision.held_contacts import check_start, held_inputs_differ
from ..sim.run.runner import Snapshot
from ..sim.run.sim_thread import SimulationThread
from ..sim.threads import toggle_single_thread
from .bake_key import BakeKey
from .bindings import APP_BINDINGS, CONTROL_KEYS_ACTIONS, TEXT_KEYS_ACTIONS
from .capture_actions import CaptureActions
from .commands import FabricCommands, SceneCommands, with_own_screenshot
from .debug_log import DebugLog
from .fabric_actions import FabricActions
from .graphics.detect import Graphics
from .help import HelpScreen
from .key_order import KeyOrder
from .memory import freeze_start_up_objects, install_acyclic_strip_divide
from .messages import Captured, FrameReady, SimDied, SimUpdated
from .panel_actions import NARROW_CLASS, WIDE_CLASS, WIDE_FROM, PanelActions
from .panels import Controls
from .pixel_preview import PixelPreview
from .preview import Preview
from .process import end_on_signals, run_in_process
from .status import Readout, StatusBar, cells
from .textual_adapter import is_select_overlay, set_color_system
from .view_actions import ViewActions

RICH_COLOR_SYSTEM = {"truecolor": "truecolor", "256": "256", "16": "standard"}
FREEZE_GC_AFTER_S = 10.0  # start-up is over by then, even without a renderer


def default_renderer_factory(**kwargs):
    from ..render.service import RenderService
    return RenderService(**kwargs)


class ClothApp(KeyOrder, ViewActions, CaptureActions, PanelActions, FabricActions, App):
    CSS_PATH = "app.tcss"
    TITLE = "cloth-tui"
    AUTO_FOCUS = None  # keys go to the app until the user picks a field
    COMMANDS = App.COMMANDS | {SceneCommands, FabricCommands}
    BINDINGS = APP_BINDINGS
    # Narrower than WIDE_FROM, the controls are a drawer over the preview (`c`), which takes
    # the width: at 80 columns a side panel would leave a 34-column picture.
    HORIZONTAL_BREAKPOINTS = [(0, NARROW_CLASS), (WIDE_FROM, WIDE_CLASS)]

    def __init__(self, scene: Scene, captures_dir: Path, *,
                 renderer_factory: Callable[..., Any] | None = None,
                 start_paused: bool = False, freeze_gc: bool = False,
                 graphics: Graphics | None = None, start_when_shown: bool = False) -> None:
        super().__init__()
        self.graphics = graphics or Graphics("blocks")  # colors: truecolor
        if graphics is not None and "TEXTUAL_COLOR_SYSTEM" not in os.environ:
            # The colour depth the terminal was found to have, not the one it announces
            # (Rich reads TERM=xterm as 16 colours).
            set_color_system(self.console, RICH_COLOR_SYSTEM[graphics.colors])
        install_acyclic_strip_divide()  # else every redrawn line is cyclic garbage
        self.scene = scene
        self.own_fabric = scene.material  # Restore defaults' fabric (fabric_actions.py)
        self.captures_dir = Path(captures_dir)
        self.renderer_factory = renderer_factory or default_renderer_factory
        self.start_paused = start_paused
        # In a browser the page shows the first picture seconds after the app starts: the
        # simulation waits for it, so a visitor sees the sheet fall rather than lie settled.
        self._start_when_shown = start_when_shown and not start_paused
        self._freeze_gc = freeze_gc  # after the first frame: start-up done
        self._preview_widget: Preview | None = None
        self._status_widget: StatusBar | None = None
        self._halt_told: str | None = None  # the runner's halt reason already notified
        self.readout = Readout()
        if graphics is not None:  # shown in the status line when it was chosen
            self.readout.graphics = graphics.label
        self.sim: SimulationThread | None = None
        self.renderer: Any = None
        self._snapshots: NewestSlot[Snapshot] = NewestSlot()  # from the simulation thread
        self._frames: NewestSlot[Frame] = NewestSlot()        # from the render thread
        self._grabbed: int | None = None
        self._cut_at: int | None = None  # the particle the knife (right-drag) last passed
        self._zoom = 1.0
        self._view_log: deque[tuple[float, str]] = deque(maxlen=8)  # for typed_digit_notice
        self._stopped = False
        self._crosshair_placed = False
        self._no_preview: str | None = None  # why there are no pictures, once known
        self.bake = BakeKey(self.captures_dir, self.notify, self.download)  # `e`: record to USD
        self.crash: Exception | None = None  # the first exception nothing caught
        self._compiling = CompileWatch()  # a first run's kernels, told in the status line
        self._debug = DebugLog.from_environment()  # timestamps of keys and frames

    def get_default_screen(self) -> Screen:
        """The first screen, born with the breakpoint class of the terminal's width: Textual
        sets it on the first resize, after the panels mount, and a class changed then
        restyles every widget; one already there changes nothing."""
        width_class = WIDE_CLASS if self.size.width >= WIDE_FROM else NARROW_CLASS
        return Screen(id="_default", classes=width_class)

    def notify(self, message: str, *, title: str = "", severity: str = "information",
               timeout: float | None = None, markup: bool = False) -> None:
        """Every notice shows its text literally: file names, keys and values in it come from
        the user, so control characters are escaped and brackets are not read as markup."""
        super().notify(escape_controls(message), title=escape_controls(title),
                       severity=severity, timeout=timeout, markup=False)

    # -- layout ---------------------------------------------------------------------------
    def compose(self) -> ComposeResult:
        with Horizontal(id="main"):
            yield self._make_preview()
            yield Controls(self.scene, id="controls")
        yield StatusBar(id="status")
        yield Footer(compact=True)

    def _make_preview(self) -> Preview:
        """True pixels where the terminal has them, half-blocks elsewhere (dithered below
        truecolor only when the depth was found out, i.e. graphics was given)."""
        if self.graphics.mode == "blocks":
            return Preview(id="preview", colors=self.graphics.colors)
        return PixelPreview(self.graphics, id="preview")

    @property
    def preview(self) -> Preview:
        return self.query_one(Preview)

    def _shown_preview(self) -> Preview | None:
        """The mounted preview, found once: a query walks the whole DOM (~2 ms a frame of
        the UI thread with the panels' widgets)."""
        if self._preview_widget is None or not self._preview_widget.is_attached:
            self._preview_widget = next(iter(self.query(Preview)), None)
        return self._preview_widget

    def _shown_status_bar(self) -> StatusBar | None:
        """The mounted status bar, found once as the preview is (none while the app is
        closing); a query five times a second took ~7 % of the UI thread at 128²."""
        if self._status_widget is None or not self._status_widget.is_attached:
            self._status_widget = next(iter(self.query(StatusBar)), None)
        return self._status_widget

    @property
    def controls(self) -> Controls:
        return self.query_one(Controls)

    def on_mount(self) -> None:
        end_on_signals(self)
        self._compiling.__enter__()  # before either thread starts compiling
        try:
            self.renderer = self.renderer_factory(
                scene=self.scene, size=(160, 90), captures_dir=self.captures_dir,
                on_frame=self._on_frame, on_event=self._on_event, preview_file=True)
            self.renderer.start()
        except Exception as e:  # no GL, no renderer: the app still simulates
            self.renderer = None
            self._show_no_preview(f"{type(e).__name__}: {e}")
        if self.renderer is None:
            self._start_when_shown = False  # no picture will come
        self._start_sim(paused=self.start_paused or self._start_when_shown)
        self.set_interval(0.2, self._refresh_status)
        self.set_timer(FREEZE_GC_AFTER_S, self._freeze_start_up)  # if no frame comes

    def _start_sim(self, paused: bool) -> None:
        if self.sim is not None:
            self.sim.stop(timeout=0.2)
        # the snapshots go from the simulation thread to the renderer and to the UI's queue
        to = [self._on_snapshot] if self.renderer is None else [self.renderer.submit,
                                                               self._on_snapshot]
        self.sim = SimulationThread(self.scene, subscribers=to, on_died=self._post_sim_died)
        self.sim.on_frame = self.bake.on_frame
        self.sim.paused = paused
        self.sim.start()

    # -- from other threads (never touch widgets here) ------------------------------------
    def _on_snapshot(self, snap) -> None:
        if self._snapshots.put(snap):
            self.post_message(SimUpdated())

    def _post_sim_died(self, error: BaseException) -> None:
        # (not `_on_sim_died`: Textual would call that for every SimDied message too)
        self.post_message(SimDied(error))

    def _on_frame(self, frame) -> None:
        if self._frames.put(frame):
            self.post_message(FrameReady())

    def _on_event(self, event) -> None:
        self.post_message(Captured(event))

    # -- messages -------------------------------------------------------------------------
    def on_sim_updated(self, _: SimUpdated) -> None:
        snap = self._snapshots.take()
        if snap is not None and self.sim is not None:
            self.readout.on_snapshot(snap.frame, snap.stats)
            halted = snap.stats.halted
            if halted and halted != self._halt_told:
                self.notify(f"Simulation stopped: {halted}", severity="error", timeout=15)
            self._halt_told = halted

    def on_frame_ready(self, _: FrameReady) -> None:
        frame = self._frames.take()
        preview = self._shown_preview()
        if frame is None or preview is None:
            return
        t0 = time.perf_counter()
        preview.show_image(frame.image)
        self.readout.on_frame(frame.render_ms)
        self._debug.line(f"frame {frame.frame} render_ms {frame.render_ms:.2f} "
                         f"ui_ms {1e3 * (time.perf_counter() - t0):.2f}", at=t0)
        self._freeze_start_up()
        if self._start_when_shown and self.sim is not None:
            self._start_when_shown = False
            self.sim.pause(False)
        if not self._crosshair_placed and self.renderer is not None:
            self._crosshair_placed = self._place_crosshair()

    def on_sim_died(self, message: SimDied) -> None:
        err = message.error
        text = f"{type(err).__name__}: {err}" if err else "unknown error"
        self.notify(f"The simulation stopped: {text}. Press r to restart.",
                    severity="error", timeout=30)

    def _show_no_preview(self, reason: str) -> None:
        """The renderer cannot start: say so where the picture would be, in the status line
        and once as a notification; the simulation runs on."""
        self._no_preview = reason
        for preview in self.query(Preview):
            preview.show_placeholder(f"no preview: {reason}")
        self.notify(f"No preview: {reason}", severity="error", timeout=30)
        self._refresh_status()

    def on_preview_resized(self, message: Preview.Resized) -> None:
        if self.renderer is not None:
            self.renderer.resize(message.width, message.height)

    # -- scene changes --------------------------------------------------------------------
    def set_value(self, dotted: str, value: Any) -> bool:
        """Apply one setting live; a refused value is reported and changes nothing. It is
        checked by the scene's validators; one that may move a held particle or an object
        (the sheet, pins, the wave, objects, the floor) also for held particles in objects,
        here, before the simulation thread builds anything. A forces, friction, damping or
        solver value, or an appearance, builds no model here."""
        try:
            new = self.scene.with_value(dotted, value)
            if held_inputs_differ(self.scene, new):
                check_start(new)  # refused here, not by the simulation thread
        except SceneError as e:
            self.notify(str(e), title="Value refused", severity="error", timeout=8)
            return False
        self.apply_scene(new, shown=True)  # the field that asked shows it (or action_toggle)
        return True

    def apply_scene(self, new: Scene, *, restart: bool = False, shown: bool = False) -> None:
        """Run `new`, a scene the caller has validated, held particles included (where an
        edit could move one: held_contacts.held_inputs_differ), which the simulation thread
        then does not check again (held_contacts.check_scene). `shown`: the caller shows
        what changed (set_value's one key, a list panel's list)."""
        self.scene = new
        if self.sim is not None:
            self.sim.submit(lambda sim, new=new: sim.set_scene(new))
            if restart:
                self.sim.submit(lambda sim: sim.reset())
                self.readout.restart()
                self._crosshair_placed = False  # back onto the (new) sheet
        if self.renderer is not None and (self.sim is None or self.sim.error is not None):
            # no simulation to carry the scene to the renderer in its next snapshot (it
            # publishes one after every command, paused too)
            self.renderer.update_scene(new)
        if not shown:
            self.controls.show_scene(new)

    def open_scene(self, name: str) -> None:
        try:
            new = load(name)
            check_start(new)
        except SceneError as e:
            self.notify(str(e), severity="error")
            return
        new, fabric = self.with_fabric_kept(name, new)
        self.apply_scene(new, restart=True)
        self.notify(f"Opened scene {name}; {fabric}")

    # -- actions --------------------------------------------------------------------------
    def check_action(self, action: str, parameters: tuple[object, ...]) -> bool | None:
        if isinstance(self.screen, HelpScreen):
            return action in ("help", "quit")  # nothing acts unseen behind the help
        if action in TEXT_KEYS_ACTIONS and (isinstance(self.focused, (Input, OptionList))
                                            or is_select_overlay(self.focused)):
            return False  # let the field (or the fabric list: its arrows) have the key
        if action in CONTROL_KEYS_ACTIONS and self.focused is not None:
            return False  # space toggles the focused switch, presses the focused button
        return True

    def get_system_commands(self, screen):
        return with_own_screenshot(super().get_system_commands(screen), self.action_screenshot)

    def _log_key(self, what: str) -> None:
        self._debug.line(f"key {what}")

    def debug_line(self, text: str) -> None:
        """A timestamped line in the debug log (CLOTH_TUI_DEBUG_LOG), when there is one."""
        self._debug.line(text)

    def action_pause(self) -> None:
        self._start_when_shown = False  # the user's choice, from now on
        if self.sim is not None:
            self.sim.pause(not self.sim.paused)
            self._log_key(f"pause {self.sim.paused}")
        self._refresh_status()

    def action_one_thread(self) -> None:
        """Physics on one thread, or back to the measured serial/parallel choice."""
        one = toggle_single_thread()
        self.notify("Physics on one thread" if one else
                    "Physics threads: one or two, whichever is measured faster")
        self._log_key("one_thread")

    def action_restart(self) -> None:
        if self.sim is None or self.sim.error is not None:  # the thread died: a new one
            self._start_sim(paused=False)
            self.notify("Simulation restarted")
        else:
            self.sim.submit(lambda sim: sim.reset())
        self.readout.restart()
        self._log_key("restart")

    def action_toggle(self, dotted: str) -> None:
        if self.set_value(dotted, not self.scene.get(dotted)):
            self._show_value(dotted)
        self._log_key(dotted)

    def _show_value(self, dotted: str) -> None:
        """The panel field of `dotted` shows the scene's value."""
        self.controls.show_value(dotted, self.scene)

    def action_unfocus(self) -> None:
        self.set_focus(None)

    def _handle_exception(self, error: Exception) -> None:
        """An exception nothing caught ends the app as any internal error of the command
        line does: one line and a log with the traceback (run_app hands the exception to
        cli.main), never Textual's full-screen traceback."""
        if self.crash is None:
            self.crash = error
        super()._handle_exception(error)  # return code 1, closes the app, tells the Pilot
        self._exit_renderables.clear()    # what Textual would print after the app closed

    async def action_quit(self) -> None:
        self.shutdown()
        self.exit(0)

    # -- status and shutdown --------------------------------------------------------------
    def _refresh_status(self) -> None:
        b = self.scene.behavior
        recording = bool(self.renderer is not None and self.renderer.recording)
        paused = bool(self.sim is not None and self.sim.paused)
        marks = self.bake.status(("", ""))[0]  # "● USD 12 · " while baking
        self.readout.compiling = self._compiling.describe()
        if self._no_preview is not None:
            marks += "[b white on red] no preview [/] · "
        bar = self._shown_status_bar()
        if bar is None:
            return
        width = bar.content_size.width or self.size.width - 2
        state, cost = self.readout.text(paused=paused, recording=recording,
                                        iterations=b.iterations, substeps=b.substeps,
                                        width=width - cells(marks))
        bar.show((marks + state, cost), self.readout.ms_history)

    def shutdown(self) -> None:
        """Stop both threads (the renderer finishes a running video); at most ~1.5 s."""
        if self._stopped:
            return
        self._stopped = True
        self._compiling.__exit__(None, None, None)
        t0 = time.perf_counter()
        if self.sim is not None:
            self.sim.stop(timeout=0.5)
        if self.renderer is not None:
            self.renderer.stop(timeout=1.0)
        self.bake.finish(timeout=5.0)  # saved, as a running video is finished
        self._debug.line(f"shutdown {1e3 * (time.perf_counter() - t0):.0f} ms")
        self._debug.close()

    def _freeze_start_up(self) -> None:
        """Once, at the first frame shown (start-up is over): see memory.py."""
        if self._freeze_gc:
            self._freeze_gc = False
            freeze_start_up_objects()

    def on_unmount(self) -> None:
        self.shutdown()


def run_app(scene: Scene, captures_dir: Path, *, app_class: type[ClothApp] = ClothApp,
            **kwargs: Any) -> int:
    """Run the app (or a subclass, e.g. the replay app, given its own keyword arguments) as
    process.run_in_process does; return its exit code."""
    return run_in_process(app_class, scene, captures_dir, **kwargs)
