"""RenderService: the one long-lived render thread of the app.

It is the only thread that ever touches VTK: it creates the Renderer (whose GL context is bound
to it), draws the newest snapshot, and hands each picture to the UI (`on_frame`), to the
preview file, to screenshots and to a running video. Every public method only records a wish
and wakes the thread, so the UI thread never waits on rendering. `on_frame` and `on_event` are
called on the render thread: the UI should forward them with `post_message`.
"""

from __future__ import annotations

import threading
import time
from collections import deque
from dataclasses import dataclass
from enum import Enum
from pathlib import Path
from typing import TYPE_CHECKING, Callable

import numpy as np

from ..newest_slot import NewestSlot
from ..sim.run.run_stats import RunStats
from .capture import CaptureError, PreviewFile, VideoWriter, ensure_folder, save_png, timestamped
from .probe import RendererUnavailable

if TYPE_CHECKING:
    from ..sim.run.runner import Snapshot

VIDEO_FPS = 30.0
MAX_REPEAT = 5              # frames a slow render may be repeated to keep the video in time
IDLE_ORBIT_PERIOD = 1 / 30  # s between redraws when auto-rotating with no new snapshots
AUTO_ROTATE_DEG_PER_S = 12.0  # one turn in 30 s, three.js OrbitControls' autoRotateSpeed 2
VIDEO_SUFFIX = ".mp4"
SCREENSHOT_HEIGHT = 720   # px; the width follows the preview's aspect ratio
VIDEO_HEIGHT = 480        # px; software GL renders 26² at this size in ~5 ms


@dataclass(frozen=True)
class Frame:
    image: np.ndarray  # (H, W, 3) uint8
    frame: int         # simulation frame shown
    render_ms: float
    sim_stats: RunStats


class CaptureKind(Enum):
    """What a CaptureEvent tells the app."""
    SCREENSHOT = "screenshot"        # saved at `path`
    VIDEO_STARTED = "video_started"  # recording to `path`
    VIDEO_SAVED = "video_saved"      # saved at `path`
    VIDEO_EMPTY = "video_empty"      # recording stopped with no frame: no file
    ERROR = "error"                  # a capture or the preview file failed (`message`)
    UNAVAILABLE = "unavailable"      # no renderer on this machine (`message` says why)
    NOTICE = "notice"                # a warning that stops nothing (a truncated texture)


@dataclass(frozen=True)
class CaptureEvent:
    kind: CaptureKind
    path: Path | None
    message: str


class RenderService:
    def __init__(self, scene, size=(640, 480), captures_dir: Path = Path("captures"),
                 on_frame: Callable[[Frame], None] | None = None,
                 on_event: Callable[[CaptureEvent], None] | None = None,
                 preview_file: bool = True):
        self._scene = scene
        self._size = (int(size[0]), int(size[1]))
        self.captures_dir = Path(captures_dir)
        self.on_frame = on_frame
        self.on_event = on_event
        self._want_preview = preview_file
        self._snapshots: NewestSlot[Snapshot] = NewestSlot()  # offered, not yet drawn
        self._commands: deque[Callable[[], bool]] = deque()
        self._wake = threading.Event()
        self._stopping = threading.Event()
        self._thread = threading.Thread(target=self._run, name="cloth-render", daemon=True)
        self._renderer = None                  # created on, and used only by, the thread
        self._recording = False                # what the UI asked for, readable at once
        self._video: VideoWriter | None = None
        self._video_t0: float | None = None    # wall time of the video's first frame
        self._last_draw: float | None = None
        self._preview: PreviewFile | None = None
        self._last_snapshot = None
        self._last_image: np.ndarray | None = None
        self.error: BaseException | None = None

    # -- UI-thread API (non-blocking) -----------------------------------------------------
    def start(self) -> "RenderService":
        if not self._thread.is_alive():
            self._thread.start()
        return self

    def stop(self, timeout: float = 1.0) -> None:
        """Finish a running video, release GL and end the thread. Waits up to `timeout`,
        or up to 10 s while a video is being finished."""
        self._stopping.set()
        self._wake.set()
        if self._video is not None or self._recording:
            timeout = max(timeout, 10.0)  # let ffmpeg write the last fragment and the name
        if self._thread.is_alive() and self._thread is not threading.current_thread():
            self._thread.join(timeout)

    def submit(self, snapshot) -> None:
        """Offer a snapshot; if several arrive before the thread is free, the newest wins."""
        if snapshot is None:
            return
        self._snapshots.put(snapshot)
        self._wake.set()

    def update_scene(self, scene) -> None:
        self._command(lambda: self._do(lambda r: r.update_scene(scene)))

    def resize(self, w: int, h: int) -> None:
        """The preview's size. While a video records, the picture keeps the video's size and
        takes this one when the recording ends."""
        def apply() -> bool:
            self._size = (int(w), int(h))
            if self._video is None:
                self._renderer.resize(*self._size)
            return True
        self._command(apply)

    def orbit(self, d_azimuth: float, d_elevation: float) -> None:
        self._command(lambda: self._do(lambda r: r.orbit(d_azimuth, d_elevation)))

    def zoom(self, factor: float) -> None:
        self._command(lambda: self._do(lambda r: r.zoom(factor)))

    def reset_camera(self) -> None:
        self._command(lambda: self._do(lambda r: r.reset_camera()))

    def screenshot(self) -> None:
        self._command(self._do_screenshot)

    def start_recording(self) -> None:
        if not self._recording:
            self._recording = True
            self._command(self._do_start_video)

    def stop_recording(self) -> None:
        if self._recording:
            self._recording = False
            self._command(self._do_stop_video)

    def toggle_recording(self) -> None:
        (self.stop_recording if self._recording else self.start_recording)()

    @property
    def recording(self) -> bool:
        return self._recording

    def pick(self, u: float, v: float) -> int | None:
        """Particle under the image point (u, v in 0..1 from the top-left) in the last frame.
        Pure NumPy on saved matrices: safe and cheap from any thread."""
        r = self._renderer
        return r.pick(u, v) if r is not None else None

    def screen_delta_to_world(self, particle: int, du: float, dv: float
                              ) -> tuple[float, float, float] | None:
        """World displacement, in the camera's view plane at `particle`'s depth in the last
        frame, that moves its picture by (du, dv) image fractions (v downward); None before
        the first frame. Like `pick`: NumPy on saved matrices, safe and cheap from any thread."""
        r = self._renderer
        return r.screen_delta_to_world(particle, du, dv) if r is not None else None

    def _command(self, fn: Callable[[], bool]) -> None:
        self._commands.append(fn)
        self._wake.set()

    # -- on the render thread -------------------------------------------------------------
    def _run(self) -> None:
        try:
            from .renderer import Renderer
            self._renderer = Renderer(self._scene, self._size, markers=True)
        except Exception as e:  # no GL, say: the app keeps running without pictures
            self.error = e
            self._recording = False
            reason = str(e) if isinstance(e, RendererUnavailable) else f"{type(e).__name__}: {e}"
            self._emit(CaptureKind.UNAVAILABLE, None, reason)
            return
        self._start_preview()
        self._report_textures()
        try:
            while not self._stopping.is_set():
                spinning = self._renderer._scene.appearance.auto_rotate
                woke = self._wake.wait(IDLE_ORBIT_PERIOD if spinning else 0.5)
                self._wake.clear()
                # Auto-rotate keeps orbiting while the simulation is paused, as the original.
                self._step(idle_redraw=spinning and not woke)
            self._step()  # last commands, e.g. a stop_recording just before stop()
        finally:
            self._finish_video()
            self._recording = False
            self._renderer.close()

    def _step(self, idle_redraw: bool = False) -> None:
        redraw = idle_redraw
        while self._commands:
            try:
                redraw |= bool(self._commands.popleft()())
            except Exception as e:
                self._emit(CaptureKind.ERROR, None, f"{type(e).__name__}: {e}")
        snapshot = self._snapshots.take()
        if snapshot is None and redraw:
            snapshot = self._last_snapshot  # camera/appearance moved: draw the same frame
        if snapshot is not None:
            self._draw(snapshot)
        self._report_textures()  # a texture is read when the scene or the cloth needs it

    def _do(self, action) -> bool:
        action(self._renderer)
        return True

    def _report_textures(self) -> None:
        notices, self._renderer.textures.notices = self._renderer.textures.notices, []
        for text in notices:
            self._emit(CaptureKind.NOTICE, None, text)

    def _draw(self, snapshot) -> None:
        t0 = time.perf_counter()
        # Auto-rotate by wall-clock time (12°/s), however often frames are drawn.
        last, self._last_draw = self._last_draw, time.monotonic()
        turn = AUTO_ROTATE_DEG_PER_S * min(self._last_draw - last, 0.2) if last else 0.0
        try:
            image = self._renderer.render(snapshot, auto_rotate_deg=turn)
        except Exception as e:
            self._emit(CaptureKind.ERROR, None, f"render failed: {type(e).__name__}: {e}")
            time.sleep(0.1)  # do not spin on a persistent failure
            return
        ms = (time.perf_counter() - t0) * 1e3
        self._last_snapshot, self._last_image = snapshot, image
        if self._video is not None:
            try:
                self._record(image)
            except CaptureError as e:
                self._video = None
                self._recording = False
                self._emit(CaptureKind.ERROR, None, str(e))
        if self._preview is not None:
            try:
                self._preview.offer(image)
            except CaptureError as e:
                self._emit(CaptureKind.ERROR, None, f"preview file: {e}")
        if self.on_frame is not None:
            try:
                self.on_frame(Frame(image, int(snapshot.frame), ms, snapshot.stats))
            except Exception:
                pass  # a UI callback bug must not stop the pictures

    def _record(self, image: np.ndarray) -> None:
        """Keep the video in real time at VIDEO_FPS whatever the render rate: skip frames
        when drawing faster, repeat the picture when slower (a few at most, so a long stall
        does not become seconds of a still image)."""
        now = time.monotonic()
        if self._video_t0 is None:
            self._video_t0 = now
        due = int((now - self._video_t0) * VIDEO_FPS) + 1 - self._video.frames
        if due > MAX_REPEAT:
            self._video_t0 += (due - MAX_REPEAT) / VIDEO_FPS
            due = MAX_REPEAT
        for _ in range(due):
            self._video.write(image)

    def _pad_still(self, video: VideoWriter) -> None:
        """A paused simulation sends no snapshots: hold the last picture up to now (at most
        MAX_REPEAT frames), so the video lasts about as long as the recording did."""
        self._video = video
        try:
            self._record(self._last_image)
        except CaptureError:
            pass  # close() reports a broken encoder
        finally:
            self._video = None

    def _start_preview(self) -> None:
        if not self._want_preview:
            return
        try:
            self._preview = PreviewFile(ensure_folder(self.captures_dir))
        except CaptureError as e:
            self._emit(CaptureKind.ERROR, None, f"preview file disabled: {e}")

    def capture_size(self, height: int) -> tuple[int, int]:
        """A capture `height` pixels tall framed like the preview (its aspect ratio), with
        even sides for H.264."""
        pw, ph = self._size
        w = max(2, int(round(height * pw / max(ph, 1) / 2)) * 2)
        return w, height

    def _do_screenshot(self) -> bool:
        """Draw the newest frame again at SCREENSHOT_HEIGHT (the preview is only as many
        pixels as the terminal has cells) and save it."""
        if self._last_snapshot is None:
            self._emit(CaptureKind.ERROR, None, "screenshot: nothing has been drawn yet")
            return False
        r = self._renderer
        shown = r.size
        try:
            if self._video is None:
                r.resize(*self.capture_size(SCREENSHOT_HEIGHT))
                image = r.render(self._last_snapshot)
                r.resize(*shown)
            else:  # recording: the picture is already at the video's size
                image = self._last_image
            folder = ensure_folder(self.captures_dir)
            path = save_png(image, timestamped(folder, "cloth", ".png"))
        except CaptureError as e:
            self._emit(CaptureKind.ERROR, None, str(e))
            return False
        self._emit(CaptureKind.SCREENSHOT, path, f"saved {path}")
        return False

    def _do_start_video(self) -> bool:
        if self._video is not None or not self._recording:
            return False
        try:
            folder = ensure_folder(self.captures_dir)
            self._video_t0 = None
            size = self.capture_size(VIDEO_HEIGHT)
            self._video = VideoWriter(timestamped(folder, "cloth", VIDEO_SUFFIX), VIDEO_FPS,
                                      size)
            self._renderer.resize(*size)  # the preview shows the same, larger picture
        except CaptureError as e:
            self._recording = False
            self._emit(CaptureKind.ERROR, None, str(e))
            return False
        self._emit(CaptureKind.VIDEO_STARTED, self._video.path, f"recording to {self._video.path}")
        return True  # draw the last picture again: a paused simulation still gets a frame

    def _do_stop_video(self) -> bool:
        self._finish_video()
        return False

    def _finish_video(self) -> None:
        video, self._video = self._video, None
        if video is None:
            return
        if video.frames and self._last_image is not None:
            self._pad_still(video)
        self._renderer.resize(*self._size)
        if video.frames == 0:  # nothing was drawn while recording: no empty file
            video.discard()
            self._emit(CaptureKind.VIDEO_EMPTY, None,
                       "nothing was drawn while recording; no video saved")
            return
        try:
            path = video.close()
        except CaptureError as e:
            self._emit(CaptureKind.ERROR, video.partial, str(e))
            return
        self._emit(CaptureKind.VIDEO_SAVED, path, f"saved {path} ({video.frames} frames)")

    def _emit(self, kind: CaptureKind, path: Path | None, message: str) -> None:
        if self.on_event is not None:
            try:
                self.on_event(CaptureEvent(kind, path, message))
            except Exception:
                pass
