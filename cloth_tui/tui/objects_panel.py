"""The Scene group's list of [[objects]]: the same rows as the scene keys, read from
SceneObject's declarations, posting `ObjectsPanel.Changed` with the whole new list."""

from __future__ import annotations

import dataclasses
from typing import Any

from textual.app import ComposeResult
from textual.containers import Horizontal, Vertical
from textual.message import Message
from textual.widgets import Button, Collapsible, Input, Label, Select

from ..scene import OBJECT_TYPES, SceneObject
from .folded_group import folded_group
from .setting_field import SettingField

OBJECT_KEYS = {f.name: f for f in dataclasses.fields(SceneObject)}


def object_key(index: int, name: str) -> str:
    return f"objects.{index}.{name}"


def object_title(index: int, obj: SceneObject) -> str:
    x, y, z = obj.center
    return f"{index + 1}. {obj.type} at ({x:g}, {y:g}, {z:g})"


class ObjectsPanel(Vertical):
    """Edit, add and remove the scene's objects."""

    DEFAULT_CSS = """
    ObjectsPanel { height: auto; margin-top: 1; }
    ObjectsPanel #add-object-row { height: 1; margin-top: 1; }
    ObjectsPanel #add-object-type { width: 14; }
    ObjectsPanel #add-object-path { width: 1fr; }
    ObjectsPanel Button { min-width: 0; width: auto; padding: 0 1; }
    ObjectsPanel Collapsible { margin-top: 0; }
    """

    class Changed(Message):
        """Posted when the user asks for these objects (not yet validated): an edited row, Add
        or Remove. `field`: the row edited, to show its last good value if refused;
        `submitted`: Enter in that row."""

        def __init__(self, objects: list[dict[str, Any]], field: SettingField | None = None,
                     submitted: bool = False) -> None:
            super().__init__()
            self.objects, self.field, self.submitted = objects, field, submitted

    def __init__(self, objects: list[SceneObject], *, id: str | None = None) -> None:
        super().__init__(id=id)
        self._objects = [dataclasses.replace(o) for o in objects]

    def compose(self) -> ComposeResult:
        yield Label(f"[b]objects[/] ({len(self._objects)})", id="objects-label")
        for i, obj in enumerate(self._objects):
            with folded_group(object_title(i, obj), True, f"object-{i}"):
                for name, spec in OBJECT_KEYS.items():
                    yield SettingField(object_key(i, name), getattr(obj, name), spec=spec)
                yield Button("Remove", id=f"remove-object-{i}", compact=True,
                             variant="error", tooltip=f"remove object {i + 1}")
        with Horizontal(id="add-object-row"):
            yield Select([(t, t) for t in OBJECT_TYPES], value=OBJECT_TYPES[0],
                         allow_blank=False, compact=True, id="add-object-type")
            yield Input(placeholder="mesh file", id="add-object-path",
                        compact=True)
            yield Button("Add", id="add-object", compact=True, variant="primary",
                         tooltip="add an object of this type")

    def _tables(self) -> list[dict[str, Any]]:
        return [dataclasses.asdict(o) for o in self._objects]

    def on_setting_field_edited(self, event: SettingField.Edited) -> None:
        event.stop()
        _, index, name = event.dotted.split(".")
        tables = self._tables()
        tables[int(index)][name] = event.value
        self.post_message(self.Changed(tables, event.field, event.submitted))

    def on_button_pressed(self, event: Button.Pressed) -> None:
        event.stop()
        button = event.button.id or ""
        tables = self._tables()
        if button.startswith("remove-object-"):
            del tables[int(button.rsplit("-", 1)[1])]
        elif button == "add-object":
            kind = self.query_one("#add-object-type", Select).value
            path = self.query_one("#add-object-path", Input).value.strip()
            tables.append({"type": kind, **({"path": path} if kind == "mesh" else {})})
        else:
            return
        self.post_message(self.Changed(tables))

    def show_objects(self, objects: list[SceneObject]) -> None:
        """Show the scene's objects: new rows when their number changed, else new values."""
        before = self._objects
        self._objects = [dataclasses.replace(o) for o in objects]
        if len(objects) != len(before):
            self.call_later(self._recompose_keeping_focus)
            return
        # Only the values that changed (an edit changes one): showing every field of every
        # row would hold the UI thread for each. None changed: all, so that a field typed
        # as "0.50" shows its canonical "0.5".
        some_changed = before != objects
        for i, obj in enumerate(objects):
            self.query_one(f"#object-{i}", Collapsible).title = object_title(i, obj)
        for field in self.walk_children(SettingField):  # no selector matching, as query's
            _, index, name = field.dotted.split(".")
            value = getattr(objects[int(index)], name)
            if not (some_changed and value == getattr(before[int(index)], name)):
                field.show(value)


    async def _recompose_keeping_focus(self) -> None:
        """New rows; focus in the list (the Add or a Remove button) stays in it, on Add,
        rather than going to whatever follows the removed button (the Scene group's next
        field, whose value the next keys would then edit)."""
        focused = self.screen.focused
        inside = focused is not None and self in focused.ancestors
        await self.recompose()
        if inside:
            self.query_one("#add-object", Button).focus()
