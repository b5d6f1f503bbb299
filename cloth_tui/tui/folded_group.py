"""The panels' collapsible groups (the scene's sections, each object, each pin group)."""

from __future__ import annotations

from textual.widgets import Collapsible

from .textual_adapter import COLLAPSED_CLASS


def folded_group(title: str, collapsed: bool, id: str) -> Collapsible:
    """A Collapsible born with its folded state's class (textual_adapter.COLLAPSED_CLASS),
    which Textual would otherwise set at mount, restyling every row in the group."""
    return Collapsible(title=title, collapsed=collapsed, id=id,
                       classes=COLLAPSED_CLASS if collapsed else None)
