"""The control panels, built from the scene schema's field metadata: one row per scene key,
a Switch for booleans, a Select for choices, an Input for numbers, vectors, colours and
textures (validated when submitted or left). Rows never change the scene themselves: they
post `SettingField.Edited` and the app decides (and may refuse, restoring the shown value).
The Scene group also lists the scene's [[objects]] (ObjectsPanel): the same rows, read from
SceneObject's declarations, which post `ObjectsPanel.Changed` with the whole new list; and its
[[pins]] (pins_panel.PinsPanel), likewise."""

from __future__ import annotations

import dataclasses
import re
import tomllib
from typing import Any

from textual.app import ComposeResult
from textual.binding import Binding
from textual.containers import Horizontal, Vertical, VerticalScroll
from textual.message import Message
from textual.widget import Widget
from textual.widgets import Button, Collapsible, Input, Label, Select, Static, Switch

from ..scene import OBJECT_TYPES, SECTION_TYPES, Scene, SceneObject, key_spec, value_type

TOP_KEYS = ("cloth.size", "cloth.resolution", "appearance.wireframe", "appearance.auto_rotate")
GROUPS = ("Forces", "Scene", "Behavior", "Appearance")
SECTION_GROUP = {"cloth": "Scene", "forces": "Forces", "scene": "Scene",
                 "behavior": "Behavior", "appearance": "Appearance"}


def group_of(dotted: str) -> str:
    if dotted in TOP_KEYS:
        return "top"
    return SECTION_GROUP[dotted.split(".")[0]]


def keys_in(group: str) -> list[str]:
    """Scene keys shown in a group, in schema order (scene section first for Scene)."""
    order = ("forces", "scene", "cloth", "behavior", "appearance")
    if group == "top":
        return list(TOP_KEYS)
    return [f"{s}.{f.name}" for s in order for f in dataclasses.fields(SECTION_TYPES[s])
            if group_of(f"{s}.{f.name}") == group]


def widget_id(dotted: str) -> str:
    return "f-" + dotted.replace(".", "-")


def format_value(value: Any) -> str:
    """Text that reads back as exactly `value` (shortest round-trip form), so Enter on an
    unchanged field changes nothing: 0.123456789 is not shown, then set, as 0.123457."""
    if isinstance(value, bool):
        return "true" if value else "false"
    if isinstance(value, float):
        text = repr(value)
        return text[:-2] if text.endswith(".0") else text  # "1", not "1.0"
    if isinstance(value, list) and any(isinstance(v, list) for v in value):
        return "[" + ", ".join(f"[{format_value(v)}]" for v in value) + "]"  # pin `at`, keys
    if isinstance(value, list):
        return ", ".join(format_value(v if isinstance(v, int) else float(v)) for v in value)
    return str(value)


def parse_text(dotted: str, text: str, spec: dataclasses.Field | None = None) -> Any:
    """Text of an Input → the Python value to validate. What cannot be parsed is returned as
    the raw string, so the scene's validation produces the one-line message. `spec`: the
    field's declaration, for keys outside the scene's sections (an object's)."""
    f = spec or key_spec(dotted)
    kind = f.metadata["kind"]
    t = value_type(f)
    text = text.strip()
    if kind == "toml":  # a pin group's rows, cols, at, keys: "0, -1" or "[[0, 0], [0, 5]]"
        try:
            return tomllib.loads(f"v = {text if text.startswith('[') else f'[{text}]'}")["v"]
        except (tomllib.TOMLDecodeError, RecursionError, ValueError):
            return text
    if kind.startswith("vec3"):
        parts = [p for p in re.split(r"[,\s]+", text.strip("[]() ")) if p]
        try:
            return [float(p) for p in parts]
        except ValueError:
            return text
    if f.metadata.get("pair"):  # "2, 0.5" (or "[2, 0.5]") is the list form, "2" one number
        parts = [p for p in re.split(r"[,\s]+", text.strip("[]() ")) if p]
        if len(parts) > 1:
            values = [_number_text(p, t) for p in parts]
            return text if any(isinstance(v, str) for v in values) else values
    return _number_text(text, t)


def _number_text(text: str, t: str) -> Any:
    """One number of type `t` read from text, or the text itself when it is none."""
    if t == "int":
        try:
            return int(text)  # exact: a float would turn 2**63 - 1 into 2**63
        except ValueError:
            pass  # "1.5", "1e3": read as a float below
    if t in ("int", "float"):
        try:
            v = float(text)
        except ValueError:
            return text
        return int(v) if t == "int" and v.is_integer() else v
    return text


def label_text(dotted: str, spec: dataclasses.Field | None = None) -> str:
    f = spec or key_spec(dotted)
    name = dotted.split(".")[-1].replace("_", " ")
    unit = f.metadata["unit"]
    return f"{name} [dim]({unit})[/]" if unit else name


class SettingField(Horizontal):
    """One scene key: a label (with unit) and the control for its type. Escape restores the
    last good value and leaves the field; Enter (the app decides) applies and moves on."""

    BINDINGS = [Binding("escape", "revert", "restore the last good value and leave the field",
                        show=False)]

    class Edited(Message):
        """The user asks for `dotted` = `value` (not yet validated)."""

        def __init__(self, field: "SettingField", dotted: str, value: Any,
                     submitted: bool = False) -> None:
            super().__init__()
            self.field, self.dotted, self.value = field, dotted, value
            self.submitted = submitted  # Enter in an Input (rather than leaving it)

    def __init__(self, dotted: str, value: Any,
                 spec: dataclasses.Field | None = None) -> None:
        super().__init__(id=widget_id(dotted) + "-row", classes="setting")
        self.dotted = dotted
        self.spec = spec or key_spec(dotted)
        self._value = value
        self.tooltip = f"{dotted}: {self.spec.metadata['doc']}"

    @property
    def last_good(self) -> Any:
        """The value shown before the edit: the scene's, as last shown."""
        return self._value

    @property
    def control(self) -> Widget:
        return self.query_one("#" + widget_id(self.dotted))

    def compose(self) -> ComposeResult:
        m, wid, v = self.spec.metadata, widget_id(self.dotted), self._value
        yield Label(label_text(self.dotted, self.spec), classes="setting-label")
        t = self.spec.type if isinstance(self.spec.type, str) else self.spec.type.__name__
        if t == "bool":
            yield Switch(value=v, id=wid)
        elif m["choices"]:
            yield Select([(c, c) for c in m["choices"]], value=v, allow_blank=False,
                         compact=True, id=wid)
        else:
            yield Input(format_value(v), id=wid, compact=True, select_on_focus=False)
            if m["kind"] == "color":
                yield Static(" ", classes="swatch", id=wid + "-swatch")

    def on_mount(self) -> None:
        self._paint_swatch()

    def _paint_swatch(self) -> None:
        """The colour itself beside its #rrggbb text (always a valid one: the last good)."""
        if self.spec.metadata["kind"] != "color":
            return  # no swatch: and a query walks the row's widgets at every show
        for swatch in self.query(".swatch"):
            swatch.styles.background = self._value
            swatch.tooltip = f"{self._value}"

    def show(self, value: Any) -> None:
        """Display `value` (the last good one) without asking for a change."""
        self._value = value
        if not self.is_mounted:
            return
        c = self.control
        if isinstance(c, Switch):
            if c.value != value:
                with c.prevent(Switch.Changed):
                    c.value = value
        elif isinstance(c, Select):
            if c.value != value:
                with c.prevent(Select.Changed):
                    c.value = value
        elif isinstance(c, Input):
            text = format_value(value)
            if c.value != text:
                with c.prevent(Input.Changed):
                    c.value = text
        self._paint_swatch()

    def action_revert(self) -> None:
        self.show(self._value)
        self.screen.set_focus(None)

    def _edited(self, value: Any) -> None:
        if value != self._value:
            self.post_message(self.Edited(self, self.dotted, value))

    def on_switch_changed(self, event: Switch.Changed) -> None:
        event.stop()
        self._edited(event.value)

    def on_select_changed(self, event: Select.Changed) -> None:
        event.stop()
        if event.value is not Select.BLANK:
            self._edited(event.value)

    def on_input_submitted(self, event: Input.Submitted) -> None:
        event.stop()
        self._commit(event.value, submitted=True)

    def on_input_blurred(self, event: Input.Blurred) -> None:
        event.stop()
        self._commit(event.value)

    def _commit(self, text: str, submitted: bool = False) -> None:
        if text.strip() != format_value(self._value) or submitted:
            value = parse_text(self.dotted, text, self.spec)
            self.post_message(self.Edited(self, self.dotted, value, submitted))


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
        """The user asks for these objects (not yet validated). `field`: the row edited, to
        show its last good value if refused; `submitted`: Enter in that row."""

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
            with Collapsible(title=object_title(i, obj), collapsed=True, id=f"object-{i}"):
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
        # row held the UI thread ~0.5 ms an edit. None changed: all, so that a field typed
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


class Controls(VerticalScroll):
    """Top-level settings and buttons, then the four collapsible groups."""

    class Command(Message):
        """A button: 'restart', 'defaults' or 'hide'."""

        def __init__(self, command: str) -> None:
            super().__init__()
            self.command = command

    def __init__(self, scene: Scene, *, id: str | None = None) -> None:
        super().__init__(id=id)
        self._scene = scene

    def compose(self) -> ComposeResult:
        from .pins_panel import PinsPanel  # here: it builds on SettingField, defined above
        for dotted in keys_in("top"):
            yield SettingField(dotted, self._scene.get(dotted))
        with Horizontal(id="buttons"):
            yield Button("Restart", id="restart", compact=True, variant="primary")
            yield Button("Restore defaults", id="defaults", compact=True, variant="warning")
            yield Button("Hide", id="hide", compact=True, tooltip="hide the controls (c)")
        for group in GROUPS:
            with Collapsible(title=group, collapsed=group != "Forces",
                             id="group-" + group.lower()):
                for dotted in keys_in(group):
                    yield SettingField(dotted, self._scene.get(dotted))
                if group == "Scene":
                    yield ObjectsPanel(self._scene.objects, id="objects")
                    yield PinsPanel(self._scene.pins, id="pins")

    def on_button_pressed(self, event: Button.Pressed) -> None:
        event.stop()
        self.post_message(self.Command(event.button.id or ""))

    def show_value(self, dotted: str, scene: Scene) -> None:
        """Show `scene`'s value of the one key `dotted` (a scene with only it changed); a
        key with no row of its own (a [material] key) shows nowhere."""
        self._scene = scene
        for field in self.query("#" + widget_id(dotted) + "-row").results(SettingField):
            field.show(scene.get(dotted))

    def show_scene(self, scene: Scene) -> None:
        """Show every value of `scene` (after a refused edit, a reset or a scene change)."""
        from .pins_panel import PinsPanel
        self._scene = scene
        for field in self.query(SettingField):
            if not field.dotted.startswith(("objects.", "pins.")):
                field.show(scene.get(field.dotted))
        self.query_one(ObjectsPanel).show_objects(scene.objects)
        self.query_one(PinsPanel).show_pins(scene.pins)


def all_panel_keys() -> list[str]:
    keys = keys_in("top")
    for g in GROUPS:
        keys += keys_in(g)
    return keys
