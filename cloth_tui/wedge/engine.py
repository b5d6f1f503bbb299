"""The Dask engine the wedge and the accuracy study share: a `LocalCluster` of worker
processes (one thread each) by default, or an existing scheduler by address; tasks submitted
at once, results taken as they finish, with progress, retries and a clean cancel.

Bounds: at most MAX_WORKERS_PER_CORE local workers per core (each is a Python process of
about 120 MB; beyond that they only contend), and never more than there are tasks (the
wedge's choice; see worker_count). A scheduler must speak within SILENT_S of accepting the
connection (a Dask scheduler sends its handshake at once); a server that accepts and stays
silent had the client wait for ever, deaf to Ctrl+C.

A worker that dies (killed, out of memory) is replaced by its nanny and the scheduler runs its
task again elsewhere (up to `distributed.scheduler.allowed-failures`, 3 by default); a task
that raises is retried RETRIES times before it counts as failed.
"""

from __future__ import annotations

import contextlib
import logging
import os
import signal
import socket
import threading
import time
from collections.abc import Callable, Sequence
from dataclasses import dataclass
from typing import Any

from ..usage import UsageError

EXTRA_HINT = "pip install 'cloth-tui[wedge]'"
RETRIES = 2                # a task that raises runs at most this many more times
CONNECT_TIMEOUT = "10s"    # to an existing scheduler
POLL_S = 0.2               # how often the wait for results looks at the stop flag
SILENT_S = 10.0            # a scheduler that says nothing this long after accepting is not one
MAX_WORKERS_PER_CORE = 4


def max_workers() -> int:
    return MAX_WORKERS_PER_CORE * (os.cpu_count() or 1)


def check_workers(requested: int) -> None:
    if requested > max_workers():
        raise UsageError(f"--workers {requested}: at most {max_workers()} "
                         f"({MAX_WORKERS_PER_CORE} per core of this machine)")


def worker_count(requested: int | None, tasks: int) -> int:
    """Local workers for `tasks` tasks: as asked (refused beyond max_workers()) but no more
    than the tasks; by default one per core."""
    if requested is not None:
        check_workers(requested)
    wanted = requested if requested is not None else (os.cpu_count() or 1)
    return max(1, min(wanted, tasks))


def hears_scheduler(address: str, stop: Callable[[], bool] = lambda: False) -> bool:
    """Connect to a tcp:// scheduler and wait for its first bytes (a Dask scheduler sends its
    handshake at once): UsageError if it refuses, closes or stays silent for SILENT_S;
    False if `stop()` turned true meanwhile. Other schemes are left to Dask."""
    scheme, _, rest = address.rpartition("://")
    host, _, port = rest.rpartition(":")
    if scheme not in ("", "tcp") or not port.isdigit():
        return True
    where = f"--scheduler {address}"
    try:
        sock = socket.create_connection((host.strip("[]") or "127.0.0.1", int(port)),
                                        timeout=SILENT_S)
    except (OSError, OverflowError) as e:
        raise UsageError(f"{where}: cannot connect: "
                         f"{getattr(e, 'strerror', None) or e}") from None
    deadline = time.monotonic() + SILENT_S
    with sock:
        sock.settimeout(POLL_S)
        while not stop():
            try:
                data = sock.recv(1)
            except TimeoutError:
                if time.monotonic() > deadline:
                    raise UsageError(f"{where}: accepted the connection but said nothing in "
                                     f"{SILENT_S:g} s (not a Dask scheduler, or a hung one)"
                                     ) from None
                continue
            except OSError as e:
                raise UsageError(f"{where}: cannot connect: {e.strerror or e}") from None
            if not data:
                raise UsageError(f"{where}: closed the connection without a word (not a "
                                 "Dask scheduler)")
            return True
    return False


def require_dask(what: str = "wedge") -> None:
    """The optional extra, or one line naming it (exit 2)."""
    try:
        import distributed  # noqa: F401
    except ImportError:
        raise UsageError(f"{what} on Dask needs the [wedge] extra: {EXTRA_HINT}") from None


@dataclass(frozen=True)
class Failed:
    """A task that raised on every try (or whose workers kept dying)."""
    reason: str


@contextlib.contextmanager
def _sigint_ignored():
    """Worker processes started now inherit SIGINT ignored: Ctrl+C in the terminal reaches
    the whole process group, and the main process, not each worker, decides what it means
    (cancel, keep what is done). Main thread only (Python cannot set handlers elsewhere)."""
    if threading.current_thread() is not threading.main_thread():
        yield
        return
    old = signal.signal(signal.SIGINT, signal.SIG_IGN)
    try:
        yield
    finally:
        signal.signal(signal.SIGINT, old)


class Engine:
    """`with Engine(workers=2) as e: e.run(fn, calls)`; `scheduler="tcp://host:8786"` uses an
    existing cluster instead (its workers need cloth-tui installed)."""

    def __init__(self, workers: int = 1, scheduler: str | None = None,
                 stop: Callable[[], bool] = lambda: False):
        if not scheduler:
            check_workers(workers)
        self.workers, self.scheduler, self.stop = workers, scheduler, stop
        self.client = self.cluster = None

    def __enter__(self) -> "Engine":
        """Connects or starts the cluster; if `stop()` turns true while a scheduler is
        awaited, there is no client and run() returns every task as cancelled."""
        require_dask()
        import distributed

        if self.scheduler:
            if not hears_scheduler(self.scheduler, self.stop):
                return self
            try:
                self.client = distributed.Client(self.scheduler, timeout=CONNECT_TIMEOUT)
            except (OSError, TimeoutError, ValueError, TypeError) as e:
                first = (str(e).strip() or type(e).__name__).splitlines()[0]
                raise UsageError(f"--scheduler {self.scheduler}: cannot connect: {first}") \
                    from None
            return self
        # numba's parallel kernels (xpbd) share the cores among the workers, not each take all
        numba_threads = max(1, (os.cpu_count() or 1) // self.workers)
        with _sigint_ignored():
            self.cluster = distributed.LocalCluster(
                n_workers=self.workers, threads_per_worker=1, processes=True,
                dashboard_address=None, silence_logs=logging.CRITICAL,
                env={"NUMBA_NUM_THREADS": str(numba_threads)})
        self.client = distributed.Client(self.cluster)
        return self

    def __exit__(self, *exc) -> None:
        if self.client is not None:
            with contextlib.suppress(Exception):
                self.client.close()
        if self.cluster is not None:
            with contextlib.suppress(Exception):
                self.cluster.close()

    def run(self, fn: Callable, calls: Sequence[tuple],
            on_done: Callable[[int, Any], None] | None = None,
            stop: Callable[[], bool] = lambda: False) -> list:
        """fn(*args) for each args in `calls`, as tasks. Returns results in the order of
        `calls`: the value, Failed(reason), or None for a task cancelled because `stop()`
        turned true. `on_done(i, result)` is called as each finishes."""
        import distributed

        if self.client is None:  # stopped before the cluster answered
            return [None] * len(calls)
        futures = [self.client.submit(fn, *args, pure=False, retries=RETRIES)
                   for args in calls]
        index = {f.key: i for i, f in enumerate(futures)}
        results: list = [None] * len(futures)
        pending = set(futures)
        while pending:
            if stop():
                self.client.cancel(list(pending), force=True)
                break
            try:
                done, pending = distributed.wait(pending, timeout=POLL_S,
                                                 return_when="FIRST_COMPLETED")
            except TimeoutError:
                continue
            for f in done:
                i = index[f.key]
                if f.status == "finished":
                    results[i] = f.result()
                elif f.status == "cancelled":
                    continue
                else:
                    e = f.exception()
                    text = (str(e).strip() or type(e).__name__).splitlines()[0]
                    results[i] = Failed(f"{type(e).__name__}: {text}")
                if on_done is not None:
                    on_done(i, results[i])
        return results

    def map(self, fn: Callable, calls: Sequence[tuple],
            on_done: Callable[[int, Any], None] | None = None) -> list:
        """run(), where any failure is an error (the accuracy study: a failed run is a bug)."""
        results = self.run(fn, calls, on_done)
        for r in results:
            if isinstance(r, Failed):
                raise RuntimeError(f"a task failed on the cluster: {r.reason}")
        return results
