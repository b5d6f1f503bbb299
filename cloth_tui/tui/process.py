"""What the app does to the process around it: it needs a writable captures folder, ends on
SIGTERM and SIGHUP as `q` does, leaves even when the terminal's shutdown hangs, shortens the
GIL's switch interval while it runs and hands back an exception that ended it. app.run_app
and ClothApp call these."""

from __future__ import annotations

import asyncio
import os
import signal
import sys
import threading
import time
from contextlib import contextmanager
from pathlib import Path
from typing import Any, Iterator, Protocol

from ..safe_text import escape_controls

# Signals that end the app as `q` does (video finished, terminal restored); exit 128 + signal.
ENDING_SIGNALS = (signal.SIGTERM, signal.SIGHUP)
# After such a signal the captures are saved; if Textual's own shutdown is still stuck this
# long later (a terminal that stopped reading, e.g. a killed window's, leaves its output queue
# full forever), the process leaves without it.
EXIT_GRACE_S = 5.0
# s: how long a thread holding the GIL keeps it from one that asks. The simulation thread
# takes the GIL back between its compiled calls of a frame; at Python's default (5 ms) each of
# those waits while the UI thread runs Python (compositing, the preview's strips), which
# costs the simulation frames (docs/app.md has the measurement).
GIL_SWITCH_INTERVAL_S = 0.0001


class Ending(Protocol):
    """What a signal asks of the app: save and stop its threads, then exit with a code."""

    def shutdown(self) -> None: ...

    def exit(self, result=None, return_code: int = 0, message=None) -> None: ...


def end_on_signals(app: Ending) -> None:
    """Without this, SIGTERM/SIGHUP kill the process mid-frame: the video stays
    `.partial.mp4` and the terminal is left in the alternate screen with the mouse on."""
    loop = asyncio.get_running_loop()
    for sig in ENDING_SIGNALS:
        try:
            loop.add_signal_handler(sig, _end_by_signal, app, sig)
        except (ValueError, RuntimeError, NotImplementedError):
            return  # not the main thread's loop: the default behaviour stays


def _end_by_signal(app: Ending, sig: int) -> None:
    app.shutdown()
    threading.Thread(target=_leave_after, args=(EXIT_GRACE_S, 128 + int(sig)),
                     name="exit-watchdog", daemon=True).start()
    app.exit(return_code=128 + int(sig))


def _leave_after(seconds: float, code: int) -> None:
    time.sleep(seconds)
    os._exit(code)  # only reached if the normal exit hung: see EXIT_GRACE_S


@contextmanager
def short_gil_switches() -> Iterator[None]:
    """GIL_SWITCH_INTERVAL_S while the block runs, the process's own interval after."""
    interval = sys.getswitchinterval()
    sys.setswitchinterval(GIL_SWITCH_INTERVAL_S)
    try:
        yield
    finally:
        sys.setswitchinterval(interval)


def run_in_process(app_class, scene, captures_dir: Path, **kwargs: Any) -> int:
    """Create the captures folder (exit 2 if impossible), run `app_class(scene,
    captures_dir, **kwargs)` with short GIL switches, return its exit code. An exception
    that ended the app (its `crash`) is raised again here, once the terminal is restored."""
    captures_dir = Path(captures_dir)
    try:
        captures_dir.mkdir(parents=True, exist_ok=True)
        if not os.access(captures_dir, os.W_OK):
            raise PermissionError(13, "not writable")
    except OSError as e:
        print(escape_controls(f"cloth-tui: error: cannot use captures folder {captures_dir}: "
                              f"{e.strerror or e}"), file=sys.stderr)
        return 2
    kwargs.setdefault("freeze_gc", True)  # process-wide, so only for the real app, not tests
    app = app_class(scene, captures_dir, **kwargs)
    with short_gil_switches():
        app.run()
    if app.crash is not None:
        raise app.crash  # the terminal is restored: cli.main logs it and prints one line
    return app.return_code or 0
