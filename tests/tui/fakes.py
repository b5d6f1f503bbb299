"""A tiny stand-in for `cloth_tui.render.service.RenderService` (same constructor and
methods), for TUI tests that must not depend on GL. It draws an orthographic front view of
the particles (x right, y up) and records what the app asked of it."""

from __future__ import annotations

import threading
from pathlib import Path

import numpy as np

from cloth_tui.render.service import CaptureEvent, CaptureKind, Frame  # GL-free


def _rgb(hex_colour: str) -> np.ndarray:
    return np.array([int(hex_colour[i:i + 2], 16) for i in (1, 3, 5)], dtype=np.uint8)


class FakeRenderService:
    instances: list["FakeRenderService"] = []

    def __init__(self, scene, size=(160, 90), captures_dir: Path = Path("."), on_frame=None,
                 on_event=None, preview_file=True):
        self.scene, self.size, self.captures_dir = scene, size, Path(captures_dir)
        self.on_frame, self.on_event = on_frame, on_event
        self.calls: list[tuple] = []
        self.recording = False
        self.started = self.stopped = False
        self.snapshot = None
        self.frozen_image: np.ndarray | None = None  # tests set this for stable snapshots
        self._lock = threading.Lock()
        FakeRenderService.instances.append(self)

    # -- the contract ---------------------------------------------------------------------
    def start(self):
        self.started = True

    def stop(self, timeout=1.0):
        self.stopped = True
        if self.recording:
            self.stop_recording()

    def submit(self, snapshot):
        self.snapshot = snapshot
        self.scene = snapshot.scene  # as the real renderer draws each snapshot's own scene
        self._draw()

    def _draw(self):
        if self.on_frame is not None and not self.stopped and self.snapshot is not None:
            s = self.snapshot
            self.on_frame(Frame(self.render(), s.frame, 1.0, s.stats))

    def update_scene(self, scene):
        self.calls.append(("update_scene", scene))
        self.scene = scene
        self._draw()

    def resize(self, w, h):
        self.calls.append(("resize", w, h))
        self.size = (w, h)
        self._draw()  # like the real service: the same snapshot again, at the new size

    def orbit(self, d_az, d_el):
        self.calls.append(("orbit", d_az, d_el))

    def zoom(self, factor):
        self.calls.append(("zoom", factor))

    def reset_camera(self):
        self.calls.append(("reset_camera",))

    def screenshot(self):
        self.calls.append(("screenshot",))
        path = self.captures_dir / f"shot-{len(self.calls)}.png"
        self._event(CaptureEvent(CaptureKind.SCREENSHOT, path, "saved"))

    def start_recording(self):
        self.recording = True
        self._event(CaptureEvent(CaptureKind.VIDEO_STARTED, self.captures_dir / "video.mp4", ""))

    def stop_recording(self):
        self.recording = False
        self._event(CaptureEvent(CaptureKind.VIDEO_SAVED, self.captures_dir / "video.mp4", ""))

    def toggle_recording(self):
        (self.stop_recording if self.recording else self.start_recording)()

    def pick(self, u, v):
        if self.snapshot is None:
            return None
        pu, pv = self._project(self.snapshot.positions)
        return int(np.argmin((pu - u) ** 2 + (pv - v) ** 2))

    def screen_delta_to_world(self, particle, du, dv):
        """The fake's orthographic front view spans twice the sheet's longer side both
        ways."""
        if self.snapshot is None or not 0 <= int(particle) < len(self.snapshot.positions):
            return None
        span = 2 * self.scene.cloth.extent()
        self.calls.append(("screen_delta_to_world", particle, du, dv))
        return (du * span, -dv * span, 0.0)

    # -- helpers --------------------------------------------------------------------------
    def _event(self, ev):
        if self.on_event is not None:
            self.on_event(ev)

    def _project(self, x):
        half = self.scene.cloth.extent()  # the view spans ±(longer side) around the origin
        return (x[:, 0] + half) / (2 * half), (half - x[:, 1]) / (2 * half)

    def render(self) -> np.ndarray:
        if self.frozen_image is not None:
            return self.frozen_image
        w, h = self.size
        img = np.empty((h, w, 3), np.uint8)
        img[:] = _rgb(self.scene.appearance.fog_color)
        if self.snapshot is not None:
            pu, pv = self._project(self.snapshot.positions)
            cols = np.clip((pu * w).astype(int), 0, w - 1)
            rows = np.clip((pv * h).astype(int), 0, h - 1)
            img[rows, cols] = _rgb(self.scene.appearance.cloth_color)
        return img
