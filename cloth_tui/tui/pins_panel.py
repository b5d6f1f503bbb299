"""The Scene group's list of pin groups ([[pins]]), as ObjectsPanel lists the objects: one
collapsible per group with a row per key (SettingField, from PinGroup's declarations), a
Remove button each, and Add. Rows never change the scene: the panel posts the whole new list
and the app decides (and may refuse, keeping the last good values)."""

from __future__ import annotations

from typing import Any

from textual.app import ComposeResult
from textual.containers import Vertical
from textual.message import Message
from textual.widgets import Button, Collapsible, Label

from ..pin_groups import PIN_KEYS, PinGroup, group_to_dict
from .folded_group import folded_group
from .setting_field import SettingField

NEW_GROUP = {"at": [[0, 0]]}  # what Add puts in: the first corner, held where it is


def pin_key(index: int, name: str) -> str:
    return f"pins.{index}.{name}"


def pin_title(index: int, group: PinGroup) -> str:
    if group.at:
        where = "at " + " ".join(f"[{r}, {c}]" for r, c in group.at[:3]) + \
            (" …" if len(group.at) > 3 else "")
    else:
        rows = "all rows" if not group.rows else f"rows {group.rows[0]}…{group.rows[1]}"
        cols = "all columns" if not group.cols else f"cols {group.cols[0]}…{group.cols[1]}"
        where = f"{rows}, {cols}"
    how = (", moving" if group.keys else
           ", offset" if any(group.offset) else "") + \
        (f", soft {group.stiffness:g}" if group.stiffness < 1 else "")
    return f"{index + 1}. {where}{how}"


class PinsPanel(Vertical):
    """Edit, add and remove the scene's pin groups."""

    DEFAULT_CSS = """
    PinsPanel { height: auto; margin-top: 1; }
    PinsPanel #add-pins-row { height: 1; margin-top: 1; }
    PinsPanel Button { min-width: 0; width: auto; padding: 0 1; }
    PinsPanel Collapsible { margin-top: 0; }
    """

    class Changed(Message):
        """Posted when the user asks for these pin groups (tables as in a scene file, not
        yet validated): an edited row, Add or Remove. `field`: the row edited, to show its
        last good value if refused; `submitted`: Enter in that row."""

        def __init__(self, pins: list[dict[str, Any]], field: SettingField | None = None,
                     submitted: bool = False) -> None:
            super().__init__()
            self.pins, self.field, self.submitted = pins, field, submitted

    def __init__(self, pins: list[PinGroup], *, id: str | None = None) -> None:
        super().__init__(id=id)
        self._pins = [group_to_dict(g) for g in pins]
        self._groups = list(pins)

    def compose(self) -> ComposeResult:
        yield Label(f"[b]pin groups[/] ({len(self._groups)})", id="pins-label")
        for i, group in enumerate(self._groups):
            with folded_group(pin_title(i, group), True, f"pins-{i}"):
                for name, spec in PIN_KEYS.items():
                    yield SettingField(pin_key(i, name), getattr(group, name), spec=spec)
                yield Button("Remove", id=f"remove-pins-{i}", compact=True, variant="error",
                             tooltip=f"remove pin group {i + 1}")
        with Vertical(id="add-pins-row"):
            yield Button("Add pin group", id="add-pins", compact=True, variant="primary",
                         tooltip="add a group holding particle [0, 0]; edit rows, cols or at")

    def on_setting_field_edited(self, event: SettingField.Edited) -> None:
        event.stop()
        _, index, name = event.dotted.split(".")
        tables = [dict(t) for t in self._pins]
        table = tables[int(index)]
        table[name] = event.value
        if name in ("rows", "cols") and table.get("at"):
            del table["at"]  # choosing a block replaces single particles
        elif name == "at" and event.value:
            table.pop("rows", None)
            table.pop("cols", None)
        if name == "keys" and event.value:
            table.pop("offset", None)  # keys give the offset over time
        for key in ("rows", "cols", "at", "keys"):
            if table.get(key) == []:
                del table[key]  # an emptied field: left out, as in a file
        self.post_message(self.Changed(tables, event.field, event.submitted))

    def on_button_pressed(self, event: Button.Pressed) -> None:
        event.stop()
        button = event.button.id or ""
        tables = [dict(t) for t in self._pins]
        if button.startswith("remove-pins-"):
            del tables[int(button.rsplit("-", 1)[1])]
        elif button == "add-pins":
            tables.append(dict(NEW_GROUP))
        else:
            return
        self.post_message(self.Changed(tables))

    def show_pins(self, pins: list[PinGroup]) -> None:
        """Show the scene's groups: new rows when their number changed, else new values."""
        count = len(self._groups)
        self._groups = list(pins)
        self._pins = [group_to_dict(g) for g in pins]
        if len(pins) != count:
            self.call_later(self.recompose)
            return
        for i, group in enumerate(pins):
            self.query_one(f"#pins-{i}", Collapsible).title = pin_title(i, group)
        for field in self.walk_children(SettingField):  # no selector matching, as query's
            _, index, name = field.dotted.split(".")
            field.show(getattr(pins[int(index)], name))
