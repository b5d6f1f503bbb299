"""cloth-tui: a cloth simulator that runs in a terminal."""

import os
import sys

__version__ = "0.1.0"


def _started_as_the_command() -> bool:
    """Whether this process is the `cloth-tui` command (its console script, or `python -m
    cloth_tui`) rather than a program or a test that imports the package. The command line
    is the interpreter's own: a worker multiprocessing spawns is given its parent's sys.argv."""
    argv = getattr(sys, "orig_argv", [])
    if (os.path.splitext(os.path.basename(sys.argv[0]))[0] == "cloth-tui"
            and sys.argv[0] in argv):
        return True
    return "-mcloth_tui" in argv or any(a == "-m" and b == "cloth_tui"
                                        for a, b in zip(argv, argv[1:]))


def end_at_start_up(_signum, _frame):
    """SIGINT from the package's first line until `cli.main` installs its guard: the command
    has done nothing yet, so it ends at once, with the guard's one line and status."""
    os.write(2, b"cloth-tui: interrupted\n")
    os._exit(130)


if _started_as_the_command():
    # As early as any of the command's code runs: the console script's and runpy's own
    # lines, and loading cli.py, come before main's guard, and Ctrl+C there would be a
    # KeyboardInterrupt traceback. _signal is the built-in module signal.py wraps, loaded
    # with the interpreter: signal.py would first import enum, milliseconds unguarded.
    import _signal

    # (a process started with SIGINT ignored, nohup or a background job, keeps ignoring it)
    if _signal.getsignal(_signal.SIGINT) is _signal.default_int_handler:
        _signal.signal(_signal.SIGINT, end_at_start_up)
