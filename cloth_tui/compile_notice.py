"""Says so while numba compiles kernels, which only the first run after an install does (its
cache then holds them): without a word, a first `cloth-tui render` sat ~50 s before its
progress bar. numba announces each real compilation (a "numba:compile" event; a kernel
loaded from the cache sends none), so a run that loads them all says nothing."""

from __future__ import annotations

import time
from typing import TextIO

HEADER = "cloth-tui: compiling kernels (first run only)…"


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
        from numba.core import event

        notice = self

        class Listener(event.Listener):
            def on_start(self, _):
                notice._on_start()

            def on_end(self, _):
                notice._on_end()

        self._listener = Listener()
        event.register("numba:compile", self._listener)
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
