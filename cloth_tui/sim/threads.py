"""Serial or parallel: which compiled kernel a stage runs, decided by measurement.

A parallel kernel meets a barrier at every colour; when another runnable process or thread
holds a core (the render thread, the UI, anything else on the machine), each barrier waits a
scheduler slice and the two-thread kernel runs tens of times slower than one thread (measured
here: 2 M projections/s against 280 M/s with other work on both cores). So the parallel kernel
is used only while it measurably wins, and contention sends the choice back to serial at once:
- the serial kernel's thread CPU time against its wall time shows preemption: when the
  thread got less than CONTENDED_CPU_SHARE of the wall time, the machine has no idle core;
- a parallel call slower than SLOWER_BY × the serial estimate switches back immediately;
- a try runs PROBE_CALLS parallel calls and is judged on the last: the first call after serial
  ones finds the data in the other core's cache (measured at 256²: 2.7–2.9 ms against
  2.0 warm and 3.1 serial), so a one-call try lost on that alone in about half the runs;
- the parallel kernel is re-tried after a backoff that doubles each time it loses (but is
  never longer than MAX_WAIT_S), and only while a core is idle now: the kernel's count of
  runnable threads, this one included, is below the cores (a losing try under load costs
  10–100 ms). The 1-minute load average,
  used only where that count is unknown, lags a new busy process by tens of seconds and
  counts this process's own two threads: on it, the 256² bench stopped trying two threads
  after running on them;
CLOTH_TUI_THREADS=1 (environment) or `force_single_thread(True)` (the app's key) keeps
everything on one thread.
"""

from __future__ import annotations

import math
import os
import time
from typing import Callable

ENV_THREADS = "CLOTH_TUI_THREADS"
CONTENDED_CPU_SHARE = 0.8
SLOWER_BY = 1.5
WINS_BY = 0.85   # parallel must take under this share of the serial time to be chosen
FIRST_PROBE = 8  # calls before the parallel kernel is first tried
PROBE_CALLS = 2  # parallel calls in one try; the verdict is on the last (see above)
MAX_BACKOFF = 4096  # calls between tries of a losing parallel kernel
# s: and at most this long: after one unlucky loss on a quiet machine, 4,096 calls of a 256²
# sheet's projection would keep it on one thread for ~16 s.
MAX_WAIT_S = 1.0
SMOOTHING = 0.2  # weight of the newest timing in a running estimate

_forced_single = False


def force_single_thread(single: bool) -> None:
    """Keep every kernel on one thread (True) or let the measured choice decide (False)."""
    global _forced_single
    _forced_single = single


def toggle_single_thread() -> bool:
    """The app's key: flip the forced single thread; returns whether one thread is now
    forced (by the key or by CLOTH_TUI_THREADS=1)."""
    force_single_thread(not _forced_single)
    return single_thread_forced()


def env_threads() -> int | None:
    """The thread limit CLOTH_TUI_THREADS asks for, or None. ValueError names a bad value."""
    value = os.environ.get(ENV_THREADS, "").strip()
    if not value:
        return None
    if not value.isdigit() or int(value) < 1:
        raise ValueError(f"{ENV_THREADS}={value!r}: expected a whole number of threads ≥ 1")
    return int(value)


def single_thread_forced() -> bool:
    limit = env_threads()
    return _forced_single or (limit is not None and limit == 1)


def load_average() -> float:
    """Runnable processes, averaged over the last minute (0 where unknown)."""
    try:
        return os.getloadavg()[0]
    except (AttributeError, OSError):
        return 0.0


def runnable_now() -> int | None:
    """Threads runnable on the machine at this instant, the caller included (the fourth
    field of /proc/loadavg); None where unknown."""
    try:
        with open("/proc/loadavg") as fh:
            return int(fh.read().split()[3].split("/")[0])
    except (OSError, IndexError, ValueError):
        return None


def spare_core() -> bool:
    """Whether the machine has a core nobody else wants now (on average, where the count of
    runnable threads is unknown)."""
    cores = usable_cores()
    running = runnable_now()
    if running is not None:
        return running < cores
    return load_average() < cores - 0.5


def usable_cores() -> int:
    try:
        return len(os.sched_getaffinity(0))
    except AttributeError:  # not Linux
        return os.cpu_count() or 1


class KernelChoice:
    """Runs `serial` or `parallel` (same arguments, same result) on each call, whichever the
    measurements favour now (see the module's docstring). `parallel` None: serial only."""

    def __init__(self, serial: Callable, parallel: Callable | None):
        self.serial = serial
        self.parallel = parallel if usable_cores() > 1 else None
        self.serial_s = 0.0    # running estimate of one serial call's wall time
        self.parallel_s = 0.0  # and of a parallel call's
        self.use_parallel = False
        self.probe_left = 0    # parallel calls still to run in the current try
        self.calls = 0
        self.parallel_calls = 0
        self.backoff = FIRST_PROBE
        self.next_probe = FIRST_PROBE
        self.next_probe_t = math.inf  # or this perf_counter time, whichever comes first
        self.contended = False  # the serial kernel was last seen preempted

    @property
    def threads(self) -> int:
        """Threads the last call used."""
        return 2 if (self.use_parallel or self.probe_left) and not single_thread_forced() else 1

    @property
    def kernel_name(self) -> str:
        return (self.parallel if self.threads > 1 else self.serial).__name__

    def __call__(self, *args) -> None:
        self.calls += 1
        if self.parallel is None or single_thread_forced():
            self.use_parallel = False
            self.serial(*args)
            return
        if self.use_parallel or self.probe_left:
            self._run_parallel(args)
        elif self._probe_due() and not self.contended and self.serial_s and spare_core():
            self.probe_left = PROBE_CALLS
            self._run_parallel(args)
        else:
            self._run_serial(args)

    def _probe_due(self) -> bool:
        return self.calls >= self.next_probe or time.perf_counter() >= self.next_probe_t

    def _run_serial(self, args) -> None:
        w0, c0 = time.perf_counter(), time.thread_time()
        self.serial(*args)
        wall, cpu = time.perf_counter() - w0, time.thread_time() - c0
        # thread_time ticks coarsely on some kernels: judge preemption on calls long enough
        if wall > 2e-4:
            self.contended = cpu < CONTENDED_CPU_SHARE * wall
        self.serial_s = _smooth(self.serial_s, wall)

    def _run_parallel(self, args) -> None:
        self.parallel_calls += 1
        t0 = time.perf_counter()
        self.parallel(*args)
        wall = time.perf_counter() - t0
        self.parallel_s = _smooth(self.parallel_s, wall) if self.use_parallel else wall
        if self.probe_left:
            self.probe_left -= 1
            if self.probe_left and wall <= SLOWER_BY * self.serial_s:
                return  # not slow enough to stop the try at once: judge its next call
            self.probe_left = 0
        if wall > SLOWER_BY * self.serial_s or self.parallel_s > WINS_BY * self.serial_s:
            # lost: back to one thread, and wait longer before trying again
            self.use_parallel = False
            self.backoff = min(2 * self.backoff, MAX_BACKOFF)
            self.next_probe = self.calls + self.backoff
            self.next_probe_t = time.perf_counter() + MAX_WAIT_S
        else:
            self.use_parallel = True
            self.backoff = FIRST_PROBE
            self.next_probe_t = math.inf
            if self.calls % 64 == 0:
                self.use_parallel = False  # a serial call now and then keeps its estimate fresh
                self.next_probe = self.calls + 2


def _smooth(estimate: float, sample: float) -> float:
    return sample if not estimate else (1.0 - SMOOTHING) * estimate + SMOOTHING * sample
