"""What long headless commands (render, bake) share: SIGINT/SIGTERM turned into a flag the
frame loop checks, so the output is finished properly rather than cut mid-write, and a
progress bar on stderr when it is a terminal. No heavy imports."""

from __future__ import annotations

import contextlib
import signal
import sys
import threading

from .safe_text import escape_controls

EXIT_BY_SIGNAL = {signal.SIGINT: 130, signal.SIGTERM: 143}


class Interrupt:
    """Within the `with`, SIGINT/SIGTERM only set `signum` (main thread only: elsewhere
    Python cannot install handlers, and the signals keep their usual effect)."""

    def __init__(self):
        self.signum: int | None = None
        self._old: dict = {}

    def __enter__(self):
        if threading.current_thread() is threading.main_thread():
            for sig in EXIT_BY_SIGNAL:
                self._old[sig] = signal.signal(sig, self._handle)
        return self

    def _handle(self, signum, _frame):
        self.signum = signum

    def __exit__(self, *exc):
        for sig, handler in self._old.items():
            signal.signal(sig, handler)

    @property
    def name(self) -> str:
        return signal.Signals(self.signum).name if self.signum is not None else ""

    def exit_status(self, done: int, total: int, kept: str) -> int:
        """After the frame loop: 0, or, when a signal stopped it, one line on stderr saying how
        far it got and what was `kept`, and the signal's exit status."""
        if self.signum is None:
            return 0
        print(escape_controls(f"cloth-tui: {self.name}: stopped after {done} of {total} frames; "
                              f"{kept}"), file=sys.stderr)
        return EXIT_BY_SIGNAL[self.signum]


class Progress:
    def __init__(self, total: int, enabled: bool, label: str = "rendering"):
        self.total, self.enabled, self.label = total, enabled, label

    def show(self, done: int) -> None:
        if not self.enabled:
            return
        width = 30
        filled = int(width * done / max(1, self.total))
        sys.stderr.write(f"\r{self.label} [{'#' * filled}{'.' * (width - filled)}] "
                         f"{done}/{self.total}")
        sys.stderr.flush()

    def end(self) -> None:
        if self.enabled:
            sys.stderr.write("\n")
            sys.stderr.flush()


@contextlib.contextmanager
def mesh_grid_progress(enabled: bool):
    """Within the `with`, each mesh object's distance grid, built as the simulation is,
    is announced on one updating stderr line (when `enabled`: stderr is a terminal)."""
    if not enabled:
        yield
        return
    from . import meshes

    shown = []

    def show(text: str) -> None:
        sys.stderr.write(f"\r{escape_controls(text)}…\x1b[K")
        sys.stderr.flush()
        shown.append(text)

    meshes.progress = show
    try:
        yield
    finally:
        meshes.progress = None
        if shown:
            sys.stderr.write("\r\x1b[K")  # the line goes: the frame progress follows
            sys.stderr.flush()
