"""Reading values that come from users' files and arguments without trusting them: numbers
that may overflow, values that may be too deep or too long to show, texture paths that may
name no file, a huge image, or a home folder that does not exist. Pure Python (the scene
loader uses it, and `cloth-tui --help` must stay fast)."""

from __future__ import annotations

import math
from pathlib import Path
from typing import Any

from .png_header import PngHeaderError, read_png_header


def finite_float(v: int | float) -> float | None:
    """`v` as a float, or None when it is not finite (an integer of hundreds of digits
    overflows the conversion)."""
    try:
        f = float(v)
    except OverflowError:
        return None
    return f if math.isfinite(f) else None


def short_repr(value: Any) -> str:
    """A short repr of a user's value for an error message: never raises (an integer past
    Python's 4300-digit repr limit, a list nested thousands deep) and never runs long."""
    if isinstance(value, int) and not isinstance(value, bool) and value.bit_length() > 200:
        return f"an integer of about {int(value.bit_length() * math.log10(2)) + 1} digits"
    try:
        shown = repr(value)
    except (ValueError, RecursionError):
        return f"a {type(value).__name__} too deep or too large to show"
    return shown if len(shown) <= 60 else shown[:57] + "..."


class PathProblem(ValueError):
    """A file name that names no file whatever is on disk; the message says why."""


def user_path(value: str) -> Path:
    """`value` as a path with `~` expanded; PathProblem for a NUL byte (no file system takes
    one) or `~nosuchuser/…` (no home folder to expand)."""
    if "\0" in value:
        raise PathProblem("a NUL byte in the file name")
    try:
        return Path(value).expanduser()
    except RuntimeError:
        raise PathProblem("no such user's home folder") from None


def texture_file_problem(value: str) -> str | None:
    """Why the PNG path `value` cannot be a texture, or None if its header is acceptable."""
    try:
        path = Path(value).expanduser()
        if not path.is_file():
            return "file not found"
        read_png_header(path)
    except RuntimeError:  # `~nosuchuser/…`: expanduser cannot find the home folder
        return "no such user's home folder"
    except PngHeaderError as e:
        return str(e)
    except OSError as e:  # a name too long, a folder without permission
        return e.strerror or type(e).__name__
    return None
