"""Standard output that fails in one line. A command's result written to a full device
(`> /dev/full`) or a closed stdout (`>&-`, where Python's sys.stdout is None and print writes
nothing) is exit status 2 and one line on stderr, never an OSError's traceback or exit 0 with
nothing written. Imports nothing heavy."""

from __future__ import annotations

import os

from .usage import UsageError

CLOSED = "standard output is closed; the result could not be written"


class OutputError(UsageError):
    """Standard output cannot be written: reported as one line, exit status 2."""


class CheckedOutput:
    """Stands in for sys.stdout: a write or flush that fails raises OutputError. A reader who
    closed the pipe (`| head`) stays a BrokenPipeError: nothing is wrong with the command."""

    def __init__(self, stream):
        self.stream = stream  # None when the process started with stdout closed

    def write(self, text: str) -> int:
        if self.stream is None:
            raise OutputError(CLOSED)
        return self._checked(self.stream.write, text)

    def writelines(self, lines) -> None:
        for line in lines:
            self.write(line)

    def flush(self) -> None:
        if self.stream is not None:
            self._checked(self.stream.flush)

    def isatty(self) -> bool:
        return self.stream is not None and self.stream.isatty()

    def __getattr__(self, name):
        return getattr(self.stream, name)

    @staticmethod
    def _checked(call, *args):
        try:
            return call(*args)
        except BrokenPipeError:
            raise
        except OSError as e:
            raise OutputError(f"cannot write to standard output: "
                              f"{e.strerror or type(e).__name__}") from None


def discard_unwritten(stream) -> None:
    """After a failed write, point the stream's file descriptor at /dev/null: what is still
    buffered goes there when the interpreter flushes at exit, instead of failing a second
    time with an "Exception ignored" traceback. A stream with no descriptor is left alone."""
    try:
        fd = stream.fileno()
    except (AttributeError, OSError, ValueError):
        return
    devnull = os.open(os.devnull, os.O_WRONLY)
    try:
        os.dup2(devnull, fd)
    finally:
        os.close(devnull)
