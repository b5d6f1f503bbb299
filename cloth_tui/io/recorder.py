"""Recording a live simulation to a USD bake: the simulation thread hands over snapshots
(`offer`, never blocks), a thread of the recorder's own writes them, so neither the
simulation nor the UI waits on USD's saves. Frames keep the simulation's numbering: time
code k is the k-th simulated frame since the recording started.

A new sheet (resolution, restart) cannot go on in the same mesh: the recording then ends
itself, finished, and `ended_by` says why."""

from __future__ import annotations

import queue
import threading
from pathlib import Path

from .frames import BakedFrame
from .mesh_sequence import BakeIOError
from .usd_bake import UsdBakeWriter

MAX_PENDING = 600  # frames queued for the writer (10 s at 60 Hz); beyond, frames are dropped


class UsdRecorder:
    def __init__(self, path: Path, scene, model):
        self.path = Path(path)
        self.model = model
        self.writer = UsdBakeWriter(self.path, scene, model)
        self.frames = 0
        self.dropped = 0
        self.error: str | None = None
        self.ended_by: str | None = None
        self._first: int | None = None
        self._last = -1
        self._queue: queue.Queue = queue.Queue(MAX_PENDING)
        self._lock = threading.Lock()
        self._ended = False
        self._thread = threading.Thread(target=self._run, name="usd-recorder", daemon=True)
        self._thread.start()

    @property
    def active(self) -> bool:
        return self.ended_by is None and self.error is None

    def offer(self, snap) -> None:
        """From the simulation thread: record this snapshot if it is a new frame."""
        if not self.active:
            return
        if snap.model is not self.model:
            self._end("the sheet was rebuilt")
            return
        if snap.frame <= self._last:  # a republished frame (pause, a command)
            return
        if self._first is None:
            self._first = snap.frame - 1
        self._last = snap.frame
        frame = BakedFrame(snap.frame - self._first, snap.t, snap.positions, snap.objects,
                           snap.alive)
        try:
            self._queue.put_nowait(frame)
        except queue.Full:
            self.dropped += 1

    def _run(self) -> None:
        while True:
            frame = self._queue.get()
            if frame is None:
                break
            if self.error is not None:
                continue
            try:
                self.writer.write(frame)
                self.frames += 1
            except BakeIOError as e:
                self.error = str(e)
        if self.error is None and not self.frames:
            self.error = "no frame was simulated while recording: nothing saved"
        elif self.error is None:
            try:
                self.writer.close()
            except BakeIOError as e:
                self.error = str(e)

    def stop(self) -> None:
        """End the recording; the recorder's thread writes what is queued and saves the
        file (see `finished`). Never waits."""
        self._end("stopped")

    def _end(self, reason: str) -> None:
        with self._lock:
            if self._ended:
                return
            self._ended = True
            if self.ended_by is None:
                self.ended_by = reason
        # put() waits while the queue is full: on a helper thread, so no caller does
        threading.Thread(target=self._queue.put, args=(None,), daemon=True).start()

    @property
    def finished(self) -> bool:
        """Stopped and saved (or failed: `error`)."""
        return not self._thread.is_alive()

    def wait(self, timeout: float) -> bool:
        self._thread.join(timeout)
        return self.finished
