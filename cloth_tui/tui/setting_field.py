"""One scene key in the control panels: a label with its unit and the control for its type
(a Switch for booleans, a Select for choices, an Input for numbers, vectors, colours and
textures, validated when submitted or left). A row never changes the scene itself: it posts
`SettingField.Edited` and the app decides (and may refuse, restoring the shown value)."""

from __future__ import annotations

import dataclasses
import re
import tomllib
from typing import Any

from textual.app import ComposeResult
from textual.binding import Binding
from textual.containers import Horizontal
from textual.message import Message
from textual.widget import Widget
from textual.widgets import Input, Label, Select, Static, Switch

from ..scene import key_spec, value_type
from .textual_adapter import VALID_INPUT_CLASS

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


# Units of keys declared without one (a share, a count per step): what the number counts.
SHOWN_UNITS = {
    "behavior.damping": "/18 ms",      # share of velocity lost per the original's step
    "behavior.error_tolerance": "of L₀",
    "behavior.tear_stretch": "of L₀",
    "behavior.iterations": "/sub",
    "behavior.substeps": "/frame",
    "behavior.max_substeps": "/frame",
    "cloth.resolution": "across",
    "cloth.pin_fraction": "share",
    "scene.friction": "μ",
    "friction": "μ",                   # an object's
    "stiffness": "share",              # a pin group's, 0–1
    "scale": "×",                      # a mesh object's
}


def unit_text(dotted: str, spec: dataclasses.Field | None = None) -> str:
    """The unit shown beside a key's value: its declared unit, else what it counts."""
    f = spec or key_spec(dotted)
    unit = f.metadata["unit"]
    if unit or f.metadata["choices"] or f.metadata["kind"] in ("color", "texture"):
        return unit
    return SHOWN_UNITS.get(dotted) or SHOWN_UNITS.get(dotted.split(".")[-1], "")


def label_text(dotted: str, spec: dataclasses.Field | None = None) -> str:
    """The key's name as a label ("gravity strength"); its unit has a column of its own."""
    return dotted.split(".")[-1].replace("_", " ")


class SettingField(Horizontal):
    """One scene key: a label (with unit) and the control for its type. Escape restores the
    last good value and leaves the field; Enter (the app decides) applies and moves on."""

    BINDINGS = [Binding("escape", "revert", "restore the last good value and leave the field",
                        show=False)]

    class Edited(Message):
        """Posted when the user flips the switch, picks an option, or submits or leaves a
        text field they changed: they ask for `dotted` = `value` (not yet validated)."""

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
        self._replaced_why: str | None = None
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
            yield Input(format_value(v), id=wid, compact=True, select_on_focus=False,
                        classes=VALID_INPUT_CLASS)  # Textual's own, given before mount
            if m["kind"] == "color":
                yield Static(" ", classes="swatch", id=wid + "-swatch")
        unit = unit_text(self.dotted, self.spec)
        if unit:
            yield Label(unit, classes="setting-unit")

    def set_replaced(self, why: str | None) -> None:
        """Show the row as replaced by the fabric (`why`: what takes its place) rather than
        as a live value, or (None) as live again. The value stays, for when the fabric
        goes."""
        if why == self._replaced_why:
            return
        self._replaced_why = why
        self.set_class(why is not None, "-replaced")
        self.tooltip = (f"{self.dotted}: not used with a fabric: {why}" if why is not None
                        else f"{self.dotted}: {self.spec.metadata['doc']}")
        if not self.is_mounted:
            return
        if why is not None and not self.query(".replaced-note"):
            self.mount(Label("by the fabric", classes="replaced-note"), after=self.control)

    def on_mount(self) -> None:
        self._paint_swatch()
        if self._replaced_why is not None:
            self.mount(Label("by the fabric", classes="replaced-note"), after=self.control)

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
