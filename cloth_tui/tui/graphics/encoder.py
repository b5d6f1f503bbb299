"""The encoding thread: turns the newest frame into terminal bytes off the UI thread.

One slot in, newest wins: a frame offered while the previous one is still being encoded
replaces the waiting one, so a slow encoder (or terminal) drops frames instead of queueing
them. `on_encoded` is called on this thread; the UI forwards it with a message.
"""

from __future__ import annotations

import threading
import time
from dataclasses import dataclass
from typing import Callable, Protocol

import numpy as np

from . import kitty, sixel

CROSSHAIR_RGB = (255, 255, 0)


@dataclass(frozen=True)
class Job:
    image: np.ndarray                   # (H, W, 3) uint8
    cols: int                           # cells the picture covers
    rows: int
    crosshair: tuple[float, float] | None  # (u, v) in [0, 1], drawn into the pixels


@dataclass(frozen=True)
class Encoded:
    data: str          # the escape sequences, written at the preview's top-left cell
    cols: int
    rows: int
    encode_ms: float


class FrameCodec(Protocol):
    def encode(self, image: np.ndarray, cols: int, rows: int) -> str: ...

    def clear(self) -> str: ...


class SixelCodec:
    """Sixel has no ids: each frame is drawn over the last at the same place."""

    def encode(self, image: np.ndarray, cols: int, rows: int) -> str:
        return sixel.encode(image)

    def clear(self) -> str:
        return ""  # the cells' next repaint covers it


def codec_for(mode: str) -> FrameCodec:
    return kitty.KittyFrames() if mode == "kitty" else SixelCodec()


def draw_crosshair(image: np.ndarray, uv: tuple[float, float], arm: int) -> np.ndarray:
    """A copy of the image with a yellow cross of `arm` pixels at (u, v)."""
    out = image.copy()
    h, w = out.shape[:2]
    x, y = int(uv[0] * w), int(uv[1] * h)
    if 0 <= x < w and 0 <= y < h:
        out[max(y - arm, 0):y + arm + 1, x] = CROSSHAIR_RGB
        out[y, max(x - arm, 0):x + arm + 1] = CROSSHAIR_RGB
    return out


class FrameEncoder:
    def __init__(self, codec: FrameCodec, on_encoded: Callable[[Encoded], None],
                 crosshair_arm: int = 6):
        self.codec = codec
        self.on_encoded = on_encoded
        self.crosshair_arm = crosshair_arm
        self.dropped = 0  # frames replaced before they were encoded
        self.encoded = 0
        self._job: Job | None = None
        self._lock = threading.Lock()
        self._wake = threading.Event()
        self._stopping = threading.Event()
        self._thread = threading.Thread(target=self._run, name="cloth-encode", daemon=True)

    def start(self) -> "FrameEncoder":
        self._thread.start()
        return self

    def offer(self, job: Job) -> None:
        with self._lock:
            if self._job is not None:
                self.dropped += 1
            self._job = job
        self._wake.set()

    def stop(self, timeout: float = 1.0) -> None:
        self._stopping.set()
        self._wake.set()
        if self._thread.is_alive():
            self._thread.join(timeout)

    def _run(self) -> None:
        while True:
            self._wake.wait()
            self._wake.clear()
            if self._stopping.is_set():
                return
            with self._lock:
                job, self._job = self._job, None
            if job is None:
                continue
            t0 = time.perf_counter()
            image = job.image
            if job.crosshair is not None:
                image = draw_crosshair(image, job.crosshair, self.crosshair_arm)
            try:
                data = self.codec.encode(image, job.cols, job.rows)
            except Exception:  # a bad frame must not end the pictures
                continue
            self.encoded += 1
            self.on_encoded(Encoded(data, job.cols, job.rows,
                                    (time.perf_counter() - t0) * 1e3))
