"""The simulation's own thread: runs a `Simulation` in real time and publishes `Snapshot`s;
other threads talk to it only through `submit` and `latest`."""

from __future__ import annotations

import threading
import time
from collections import deque
from typing import TYPE_CHECKING, Callable, Sequence

from ...newest_slot import NewestSlot
from .run_stats import RunStats
from .runner import Simulation, Snapshot

if TYPE_CHECKING:
    from ...scene import Scene

MAX_CATCH_UP = 6  # frames (100 ms at 60 Hz) the thread may run back to back to keep time
PAUSED_POLL_S = 0.25  # s: how long a paused thread sleeps when no command wakes it
STATS_INTERVAL = 0.2  # s of wall time between full statistics in the published snapshots
# A catch-up run of frames longer than this publishes as it goes: a sheet too large for real
# time is always catching up, and publishing once per MAX_CATCH_UP frames would show only a
# sixth of the frames it simulates.
PUBLISH_INTERVAL = 1.0 / 60.0  # s


class SimulationThread:
    """Runs a Simulation in real time (one frame per 1/frame_rate wall seconds, or as fast as
    it can) on a daemon thread. Other threads talk to it only through `submit` and read
    `latest`. Each of `subscribers` (the renderer, the UI's queue) is called from the
    simulation thread with every snapshot it publishes: the first as the thread starts
    (a picture and statistics even when paused), then after frames (catching up, several
    frames are published as one) and after every command. `on_died` is called there once
    with the exception that ended the thread. `on_frame`, if set, is called there after
    every frame simulated (a recorder that needs them all); it may read the Simulation, not
    keep it."""

    def __init__(self, scene: Scene, subscribers: Sequence[Callable[[Snapshot], None]] = (),
                 on_died: Callable[[BaseException], None] | None = None):
        self.sim = Simulation(scene)
        self.subscribers = tuple(subscribers)
        self.on_died = on_died
        self.on_frame: Callable[[Simulation], None] | None = None
        self.paused = False
        self._commands: deque[Callable[[Simulation], None]] = deque()
        self._stop = threading.Event()
        self._wake = threading.Event()
        self._latest: NewestSlot[Snapshot] = NewestSlot(self.sim.snapshot())
        self._stats: RunStats | None = None  # the last full statistics published, and when
        self._stats_t = 0.0
        self._thread = threading.Thread(target=self._run, name="cloth-sim", daemon=True)
        self.error: BaseException | None = None

    def start(self) -> "SimulationThread":
        self._thread.start()
        return self

    def stop(self, timeout: float = 1.0) -> None:
        self._stop.set()
        self._wake.set()
        self._thread.join(timeout)

    def pause(self, paused: bool) -> None:
        """Pause or resume; the thread publishes a snapshot at once either way."""
        self.paused = paused
        self.submit(lambda sim: None)

    def submit(self, command: Callable[[Simulation], None]) -> None:
        """Run `command(sim)` on the simulation thread between frames."""
        self._commands.append(command)
        self._wake.set()

    @property
    def latest(self) -> Snapshot:
        return self._latest.newest

    def _publish(self, full: bool) -> None:
        """Positions every frame; the full statistics (per-edge stretch, energy: a pass over
        every constraint) only every STATS_INTERVAL s, the rate the status line shows them,
        or when a command changed the run. Between, the last full set is carried with this
        frame's cheap numbers."""
        now = time.perf_counter()
        if full or self._stats is None or now - self._stats_t >= STATS_INTERVAL:
            snap = self.sim.snapshot()
            self._stats, self._stats_t = snap.stats, now
        else:
            snap = self.sim.snapshot(self._stats)
        self._latest.put(snap)
        self._hand_over(snap)

    def _hand_over(self, snap: Snapshot) -> None:
        for subscriber in self.subscribers:
            subscriber(snap)

    def _run(self) -> None:
        """Frames are due every 1/frame_rate s of wall time. A late thread (the GIL held by the
        renderer or the UI, a slow frame) catches up with up to MAX_CATCH_UP frames at once,
        so the simulation keeps real time; further behind than that, it drops the backlog
        rather than run ever faster. Quick catch-up frames are published as one; a run that
        takes longer than PUBLISH_INTERVAL publishes on the way."""
        next_t = time.perf_counter()  # when the next frame is due
        try:
            self._hand_over(self.latest)
            while not self._stop.is_set():
                changed = commanded = False
                while self._commands:
                    self._commands.popleft()(self.sim)
                    changed = commanded = True
                now = time.perf_counter()
                if self.paused:
                    next_t = now
                else:
                    period = 1.0 / self.sim.scene.behavior.frame_rate
                    published_t = now
                    for _ in range(MAX_CATCH_UP):
                        if now < next_t:
                            break
                        self.sim.advance_frame()
                        if self.on_frame is not None:
                            self.on_frame(self.sim)
                        next_t += period
                        changed = True
                        if time.perf_counter() - published_t >= PUBLISH_INTERVAL:
                            self._publish(full=commanded)
                            published_t = time.perf_counter()
                            changed = commanded = False
                    if now >= next_t:
                        next_t = now + period
                if changed:
                    self._publish(full=commanded)
                wait = next_t - time.perf_counter() if not self.paused else PAUSED_POLL_S
                if wait > 0:
                    self._wake.wait(wait)
                    self._wake.clear()
        except BaseException as e:  # reported to the UI, never lost silently
            self.error = e
            if self.on_died is not None:
                self.on_died(e)
