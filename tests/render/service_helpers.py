"""What the capture, service and replay tests share: a counter of a written video's frames
and a collector of what a render service hands its callbacks."""

from __future__ import annotations

import queue
import threading

from cloth_tui.render.service import CaptureEvent, CaptureKind, Frame


def count_frames(path) -> int:
    """The frames in the video at `path`, as a player reads them."""
    import imageio.v2 as iio
    with iio.get_reader(str(path)) as reader:
        return sum(1 for _ in reader)


class Collector:
    def __init__(self):
        self.frames: queue.Queue[Frame] = queue.Queue()
        self.events: queue.Queue[CaptureEvent] = queue.Queue()
        self.threads: set[str] = set()

    def on_frame(self, frame):
        self.threads.add(threading.current_thread().name)
        self.frames.put(frame)

    def on_event(self, event):
        self.events.put(event)

    def event(self, kind, timeout=20):
        while True:
            e = self.events.get(timeout=timeout)
            if e.kind == kind:
                return e
            assert e.kind != CaptureKind.ERROR, e.message
