"""The control panels, built from the scene schema's field metadata: one row per scene key
(setting_field.SettingField). The Scene group also lists the scene's [[objects]]
(objects_panel.ObjectsPanel) and its [[pins]] (pins_panel.PinsPanel); the Fabric group
(fabric_panel.FabricPanel) its [material], and while one is on, the rows of the keys it
replaces say so."""

from __future__ import annotations

import dataclasses

from textual.app import ComposeResult
from textual.containers import Horizontal, VerticalScroll
from textual.message import Message
from textual.widgets import Button

from ..materials.catalogue import REPLACEABLE, replaced_keys
from ..materials.section import is_material_key
from ..scene import SECTION_TYPES, Scene
from .fabric_panel import FabricPanel
from .fabric_values import PREFIX
from .folded_group import folded_group
from .objects_panel import ObjectsPanel
from .pins_panel import PinsPanel
from .setting_field import (SettingField, format_value, label_text,  # noqa: F401 (re-exported)
                            parse_text, widget_id)

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


class Controls(VerticalScroll):
    """Top-level settings and buttons, then the collapsible groups: Fabric and the four of
    the scene's sections."""

    class Command(Message):
        """Posted when the user presses a button: `command` is 'restart', 'defaults' or
        'hide'."""

        def __init__(self, command: str) -> None:
            super().__init__()
            self.command = command

    def __init__(self, scene: Scene, *, id: str | None = None) -> None:
        super().__init__(id=id)
        self._scene = scene

    def compose(self) -> ComposeResult:
        for dotted in keys_in("top"):
            yield SettingField(dotted, self._scene.get(dotted))
        with Horizontal(id="buttons"):
            yield Button("Restart", id="restart", compact=True, variant="primary")
            yield Button("Restore defaults", id="defaults", compact=True, variant="warning")
            yield Button("Hide", id="hide", compact=True, tooltip="hide the controls (c)")
        with folded_group("Fabric", self._scene.material is None, "group-fabric"):
            yield FabricPanel(self._scene.material, id="fabric")
        for group in GROUPS:
            with folded_group(group, group != "Forces", "group-" + group.lower()):
                for dotted in keys_in(group):
                    yield SettingField(dotted, self._scene.get(dotted))
                if group == "Scene":
                    yield ObjectsPanel(self._scene.objects, id="objects")
                    yield PinsPanel(self._scene.pins, id="pins")

    def on_button_pressed(self, event: Button.Pressed) -> None:
        event.stop()
        self.post_message(self.Command(event.button.id or ""))

    def watch_has_focus(self, has_focus: bool) -> None:
        """Restyle the panel itself (its border, its scrollbar) when it takes or loses focus,
        as a click between its fields does. Textual would restyle the panel and all ~700
        widgets in it, a pause of the UI thread, though no rule of a row depends on the
        panel's focus."""
        self.app.stylesheet.update_nodes([self], animate=False)

    def on_mount(self) -> None:
        self._show_replaced(self._scene)

    def show_value(self, dotted: str, scene: Scene) -> None:
        """Show `scene`'s value of the one key `dotted` (a scene with only it changed); a
        [material] key shows in the Fabric group."""
        self._scene = scene
        if is_material_key(dotted):
            self.show_fabric(scene)
            return
        for field in self.query("#" + widget_id(dotted) + "-row").results(SettingField):
            field.show(scene.get(dotted))

    def show_scene(self, scene: Scene) -> None:
        """Show every value of `scene` (after a refused edit, a reset or a scene change)."""
        self._scene = scene
        for field in self.query(SettingField):
            if not field.dotted.startswith(("objects.", "pins.", PREFIX)):
                field.show(scene.get(field.dotted))
        self.query_one(ObjectsPanel).show_objects(scene.objects)
        self.query_one(PinsPanel).show_pins(scene.pins)
        self.show_fabric(scene)

    def show_fabric(self, scene: Scene) -> None:
        """The Fabric group shows `scene`'s fabric; the keys it replaces say so."""
        self._scene = scene
        self.query_one(FabricPanel).show_fabric(scene.material)
        self._show_replaced(scene)

    def _show_replaced(self, scene: Scene) -> None:
        replaced = {} if scene.material is None else replaced_keys(scene.material.material)
        for dotted in REPLACEABLE:
            for field in self.query("#" + widget_id(dotted) + "-row").results(SettingField):
                field.set_replaced(replaced.get(dotted))


def all_panel_keys() -> list[str]:
    keys = keys_in("top")
    for g in GROUPS:
        keys += keys_in(g)
    return keys
