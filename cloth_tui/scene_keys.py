"""How a scene key is declared (scene.py's sections, and each shape's [[objects]] keys in
sim/shapes/), and the error a refused scene raises. Apart from scene.py so that the shape
modules, which scene.py reads its object keys from, can declare theirs without a circle."""

from __future__ import annotations

from dataclasses import field
from typing import Any

from .safe_text import escape_controls

SECTIONS = ("cloth", "forces", "scene", "behavior", "appearance")  # a scene file's tables

# A direction shorter than this is refused: the kernels normalise it, and the square of a
# length near the subnormal range underflows to 0 (a division by zero) or loses its digits.
MIN_DIRECTION_NORM = 1e-6


class SceneError(ValueError):
    """A scene document, value or override that cannot be accepted. The message is one line,
    with any control character from the user's keys, values or file names escaped."""

    def __init__(self, message: str) -> None:
        super().__init__(escape_controls(message))


def key(default: Any, doc: str, *, unit: str = "", lo: float | None = None,
        hi: float | None = None, lo_open: bool = False, hi_open: bool = False,
        choices: tuple[str, ...] | None = None, kind: str = "",
        pair: tuple[str, str] | None = None) -> Any:
    """Declare a scene key: default, help text, unit and what values are allowed. `pair`
    names the two entries of the list the key also accepts in place of one number (each
    entry within the same range), as in [width, length]."""
    meta = dict(doc=doc, unit=unit, lo=lo, hi=hi, lo_open=lo_open, hi_open=hi_open,
                choices=choices, kind=kind, pair=pair)
    if isinstance(default, list):
        return field(default_factory=lambda: list(default), metadata=meta)
    return field(default=default, metadata=meta)


def vec3(default: list[float], doc: str, *, unit: str = "", nonzero: bool = False) -> Any:
    """A 3-vector; `nonzero` marks a direction, whose length must be at least
    MIN_DIRECTION_NORM so that it can be normalised."""
    return key(default, doc, unit=unit, kind="vec3_nonzero" if nonzero else "vec3")
