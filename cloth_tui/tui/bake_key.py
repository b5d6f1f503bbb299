"""The `e` key: record the live simulation to a USD bake in the captures folder, as `v`
records a video. The recorder writes on its own thread (io.recorder); this keeps the state
the app shows: a mark in the status line while recording, a notice when the file is saved."""

from __future__ import annotations

import time
from pathlib import Path
from typing import Callable

from ..io.mesh_sequence import BakeIOError
from ..io.usd_bake import missing_usd_message
from ..sim.run.run_stats import RunStats


class BakeKey:
    def __init__(self, captures_dir: Path, notify: Callable[..., None],
                 on_saved: Callable[[Path], str] = lambda path: ""):
        self.captures_dir = Path(captures_dir)
        self.notify = notify
        self.on_saved = on_saved  # a saved bake's path: what to add to its notice
        self.recorder = None  # io.recorder.UsdRecorder, from `e` until its file is saved

    @property
    def recording(self) -> bool:
        return self.recorder is not None and self.recorder.ended_by is None

    def on_frame(self, sim) -> None:
        """From the simulation thread, after every frame simulated (SimulationThread.on_frame):
        a bake has every frame, also those the app shows as one while catching up."""
        recorder = self.recorder
        if recorder is not None and recorder.ended_by is None:
            recorder.offer(sim.snapshot(stats=RunStats()))

    def toggle(self, snap) -> None:
        """Start a bake from this snapshot's sheet, or stop the running one."""
        if self.recorder is not None:
            if self.recording:
                self.recorder.stop()  # saved on the recorder's thread; status() tells
            else:
                self.notify("still saving the last bake", severity="warning")
            return
        message = missing_usd_message()
        if message or snap is None:
            self.notify(message or "no simulation to bake", severity="error", timeout=10)
            return
        from ..io.recorder import UsdRecorder

        stamp = time.strftime("%Y%m%d-%H%M%S")
        path, k = self.captures_dir / f"bake-{stamp}.usdc", 1
        while path.exists():
            k += 1
            path = self.captures_dir / f"bake-{stamp}-{k}.usdc"
        try:
            self.captures_dir.mkdir(parents=True, exist_ok=True)
            self.recorder = UsdRecorder(path, snap.scene, snap.model)
        except (OSError, BakeIOError) as e:
            self.notify(f"cannot bake to {path}: {e}", severity="error", timeout=10)
            return
        self.notify(f"Baking to {path}")

    def status(self, text: tuple[str, str]) -> tuple[str, str]:
        """The status line with the bake's mark while recording; a finished bake's notice."""
        recorder = self.recorder
        if recorder is None:
            return text
        if recorder.ended_by is None and recorder.error:
            recorder.stop()
        if recorder.ended_by is None:
            return (f"[b white on dark_blue] ● USD {recorder.frames} [/] · {text[0]}", text[1])
        if recorder.finished:
            self.recorder = None
            if recorder.error:
                self.notify(recorder.error, title="Bake failed", severity="error", timeout=10)
            else:
                why = "" if recorder.ended_by == "stopped" else f" ({recorder.ended_by})"
                self.notify(f"Bake saved: {recorder.path}, {recorder.frames} frames{why}"
                            f"{self.on_saved(recorder.path)}")
        return text

    def finish(self, timeout: float) -> None:
        """At quit: stop and save, as a running video is finished."""
        if self.recorder is not None:
            self.recorder.stop()
            self.recorder.wait(timeout)
