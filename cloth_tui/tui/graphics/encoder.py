"""The encoding thread: prepares the newest frame off the UI thread (kitty's compression,
sixel's dither and encoding); the UI thread only asks the codec for the bytes that show it.

One slot in, newest wins: a frame offered while the previous one is still being encoded
replaces the waiting one, so a slow encoder (or terminal) drops frames instead of queueing
them. `on_encoded` is called on this thread; the UI forwards it with a message.
"""

from __future__ import annotations

import threading
import time
from dataclasses import dataclass
from typing import Any, Callable, Protocol

import numpy as np

from ...newest_slot import NewestSlot
from . import kitty, sixel
from .layout import Layout

CROSSHAIR_RGB = (255, 255, 0)


@dataclass(frozen=True)
class Job:
    image: np.ndarray                   # (H, W, 3) uint8
    layout: Layout                      # where it goes
    crosshair: tuple[float, float] | None  # (u, v) in [0, 1], drawn into the pixels


@dataclass(frozen=True)
class Encoded:
    frame: Any         # the codec's prepared frame, for its `show`
    layout: Layout     # the layout it was prepared for
    encode_ms: float


class FrameCodec(Protocol):
    def prepare(self, image: np.ndarray, layout: Layout) -> Any:
        """On the encoding thread: the costly part, touching no state."""

    def show(self, frame: Any, layout: Layout) -> str | None:
        """On the UI thread: the bytes that put a prepared frame on the screen in `layout`,
        or None if the frame cannot be shown in it."""

    def relayout(self, layout: Layout) -> str:
        """On the UI thread: the bytes that move the picture on screen into a new layout."""

    def clear(self) -> str:
        """On the UI thread: the bytes that take the picture off the screen."""


def codec_for(mode: str) -> FrameCodec:
    return kitty.KittyFrames() if mode == "kitty" else sixel.SixelFrames()


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
        self.encoded = 0
        self._jobs: NewestSlot[Job] = NewestSlot()
        self._wake = threading.Event()
        self._stopping = threading.Event()
        self._thread = threading.Thread(target=self._run, name="cloth-encode", daemon=True)

    def start(self) -> "FrameEncoder":
        self._thread.start()
        return self

    @property
    def dropped(self) -> int:
        """Frames replaced before they were encoded."""
        return self._jobs.dropped

    def offer(self, job: Job) -> None:
        self._jobs.put(job)
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
            job = self._jobs.take()
            if job is None:
                continue
            t0 = time.perf_counter()
            image = job.image
            if job.crosshair is not None:
                image = draw_crosshair(image, job.crosshair, self.crosshair_arm)
            try:
                frame = self.codec.prepare(image, job.layout)
            except Exception:  # a bad frame must not end the pictures
                continue
            self.encoded += 1
            self.on_encoded(Encoded(frame, job.layout, (time.perf_counter() - t0) * 1e3))
