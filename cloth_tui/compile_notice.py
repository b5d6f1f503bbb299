"""Says so while numba compiles kernels, which only the first run after an install does (its cache
then holds them): without a word, a first `cloth-tui render` would sit silent for the best part
of a minute before its progress bar. numba announces each real compilation (a "numba:compile"
event; a kernel loaded from the cache sends none), so a run that loads them all says nothing."""

from __future__ import annotations

import threading
import time
from typing import TextIO

HEADER = "cloth-tui: compiling kernels (first run only)…"


def _listen(on_start, on_end):
    """Registers a numba listener calling on_start/on_end around every compilation; returns
    it for event.unregister."""
    from numba.core import event

    class Listener(event.Listener):
        def on_start(self, _):
            on_start()

        def on_end(self, _):
            on_end()

    listener = Listener()
    event.register("numba:compile", listener)
    return listener


class CompileNotice:
    """`with CompileNotice(stream, live):` around the work. `live` (a terminal): one line
    counting the kernels compiled so far and the seconds spent; otherwise a line when
    compiling starts and one when `finish` is called. Call `finish` where the compiling is
    over (after the first frame), so a progress line starts on a line of its own."""

    def __init__(self, stream: TextIO, live: bool) -> None:
        self.stream, self.live = stream, live
        self.compiled = 0
        self._depth = 0  # a kernel's compilation compiles the kernels it calls, nested
        self._started: float | None = None  # this phase of compiling, if one is open
        self._listener = None

    def __enter__(self) -> "CompileNotice":
        self._listener = _listen(self._on_start, self._on_end)
        return self

    def __exit__(self, *exc) -> None:
        from numba.core import event

        event.unregister("numba:compile", self._listener)
        self.finish()

    def _on_start(self) -> None:
        self._depth += 1
        if self._started is None:
            self._started = time.monotonic()
            self._write(HEADER if self.live else HEADER + "\n")

    def _on_end(self) -> None:
        self._depth -= 1
        if self._depth == 0:
            self.compiled += 1
            if self.live:
                self._write(f"\r{HEADER} {self.compiled} compiled, "
                            f"{time.monotonic() - self._started:.0f} s")

    def finish(self) -> None:
        """End the notice's line (if compiling happened since the last call)."""
        if self._started is None:
            return
        took = time.monotonic() - self._started
        self._started = None
        self._write("\n" if self.live else
                    f"cloth-tui: {self.compiled} kernels compiled in {took:.0f} s; later runs "
                    f"load them from numba's cache\n")

    def _write(self, text: str) -> None:
        self.stream.write(text)
        self.stream.flush()


class CompileWatch:
    """For the app, where no stream can be written: counts the kernels numba compiles on any
    thread (the simulation's and the renderer's each compile their own on a first run) so the
    status line can say so. `with CompileWatch() as watch:` around the app's life;
    `describe()` is the status line's words while compiling, else ""."""

    LINGER_S = 2.0  # said this long after a kernel is done, so the gaps between kernels
    # (numba compiles one at a time) do not make the words flicker

    def __init__(self) -> None:
        self._lock = threading.Lock()
        self._depth: dict[int, int] = {}  # per thread: nested compilations open
        self.compiled = 0
        self._started: float | None = None  # when this phase of compiling began
        self._compiled_before = 0  # kernels compiled in earlier phases
        self._last_end = 0.0
        self._listener = None

    def __enter__(self) -> "CompileWatch":
        self._listener = _listen(self._on_start, self._on_end)
        return self

    def __exit__(self, *exc) -> None:
        """Safe to call twice, or without __enter__ (an app that never mounted)."""
        if self._listener is None:
            return
        from numba.core import event

        event.unregister("numba:compile", self._listener)
        self._listener = None

    def _on_start(self) -> None:
        with self._lock:
            key = threading.get_ident()
            now = time.monotonic()
            if self._started is None or (not self._depth
                                         and now - self._last_end > self.LINGER_S):
                # a new phase (a kernel first needed later, as wind turned on): counted
                # and timed from here, not from the session's first compile
                self._started = now
                self._compiled_before = self.compiled
            self._depth[key] = self._depth.get(key, 0) + 1

    def _on_end(self) -> None:
        with self._lock:
            key = threading.get_ident()
            self._depth[key] = self._depth.get(key, 1) - 1
            if self._depth[key] <= 0:
                del self._depth[key]
                self.compiled += 1
                self._last_end = time.monotonic()

    def describe(self, now: float | None = None) -> str:
        """"compiling kernels (first run only)… 12 compiled, 40 s" while kernels compile
        (and LINGER_S after the last), else ""."""
        now = time.monotonic() if now is None else now
        with self._lock:
            if self._started is None:
                return ""
            if not self._depth and now - self._last_end > self.LINGER_S:
                return ""
            return (f"compiling kernels (first run only)… "
                    f"{self.compiled - self._compiled_before} compiled, "
                    f"{now - self._started:.0f} s")
