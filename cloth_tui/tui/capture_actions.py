"""The app's capture actions and their reports: screenshot, video, USD bake and saving the
scene. A mixin of `ClothApp`, which owns the renderer, the bake key and the captures folder.

Every capture is written to the captures folder. Served to a web browser (`cloth-tui serve`)
that folder is on the server, so each capture is also handed to the browser as a download.
"""

from __future__ import annotations

from pathlib import Path
from typing import Any, Callable

from textual import events

from ..render.capture import timestamped
from ..render.service import CaptureKind
from ..scene import Scene, SceneError
from ..scene_files import save as save_scene
from ..sim.run.sim_thread import SimulationThread
from .bake_key import BakeKey
from .messages import Captured


DOWNLOADING = " (downloading to your browser)"


class CaptureActions:
    """Needs from the app: `scene`, `sim`, `renderer` (or None), `bake`, `captures_dir`,
    `notify`, `_show_no_preview` and `_refresh_status`, and Textual's `is_web` and
    `deliver_binary`."""

    scene: Scene
    sim: SimulationThread | None
    renderer: Any
    bake: BakeKey
    captures_dir: Path
    notify: Callable[..., None]
    _show_no_preview: Callable[[str], None]
    _refresh_status: Callable[[], None]
    is_web: bool
    deliver_binary: Callable[..., str | None]

    def download(self, path: Path | str | None) -> str:
        """In a browser, start sending the capture at `path` to it as a download (Textual
        streams it in chunks on request); in a terminal, nothing. What to add to the notice."""
        if not self.is_web or path is None:
            return ""
        try:
            self.deliver_binary(Path(path), name=Path(path).name)
        except OSError as e:  # gone or unreadable since it was written
            self.notify(f"cannot download {path}: {e.strerror or e}", severity="error")
            return ""
        return DOWNLOADING

    def on_delivery_failed(self, event: events.DeliveryFailed) -> None:
        self.notify(f"download of {event.name} failed: {event.exception}",
                    title="Download failed", severity="error", timeout=10)

    def on_captured(self, message: Captured) -> None:
        ev = message.event
        if ev.kind == CaptureKind.UNAVAILABLE:
            self._show_no_preview(ev.message)
        elif ev.kind == CaptureKind.ERROR:
            self.notify(ev.message or "capture failed", title="Capture failed",
                        severity="error", timeout=10)
        elif ev.kind == CaptureKind.SCREENSHOT:
            self.notify(f"Screenshot saved: {ev.path}{self.download(ev.path)}")
        elif ev.kind == CaptureKind.VIDEO_STARTED:
            self.notify(f"Recording to {ev.path}" if ev.path else "Recording…")
        elif ev.kind == CaptureKind.VIDEO_SAVED:
            self.notify(f"Video saved: {ev.path}{self.download(ev.path)}")
        elif ev.kind == CaptureKind.VIDEO_EMPTY:
            self.notify(f"Nothing recorded: {ev.message}", severity="warning")
        elif ev.kind == CaptureKind.NOTICE:
            self.notify(ev.message, severity="warning", timeout=10)
        self._refresh_status()

    def action_screenshot(self) -> None:
        if self.renderer is None:
            self.notify("no renderer: cannot take a screenshot", severity="error")
        else:
            self.renderer.screenshot()

    def action_video(self) -> None:
        if self.renderer is None:
            self.notify("no renderer: cannot record", severity="error")
        else:
            self.renderer.toggle_recording()

    def action_bake(self) -> None:
        self.bake.toggle(self.sim.latest if self.sim is not None else None)
        self._refresh_status()

    def action_save_scene(self) -> None:
        path = timestamped(self.captures_dir, "scene", ".toml")  # -2, -3… within a second
        try:
            save_scene(self.scene, path)
        except SceneError as e:
            self.notify(str(e), title="Save failed", severity="error")
            return
        self.notify(f"Scene saved: {path}{self.download(path)}")
