"""The one error the materials package raises."""

from __future__ import annotations

from ..safe_text import escape_controls


class MaterialError(ValueError):
    """A material table, value or preset file that cannot be accepted. The message is one
    line, with any control character from the user's text escaped."""

    def __init__(self, message: str) -> None:
        super().__init__(escape_controls(message))
