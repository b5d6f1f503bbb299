"""What the Fabric group and the palette's "Fabric: NAME" ask of the app: a preset chosen, a
fabric value edited; and what becomes of the chosen fabric when another scene opens (kept,
unless that scene names its own) or the defaults are restored (the scene's own). A mixin
of `ClothApp`, which owns the scene and applies it."""

from __future__ import annotations

import tomllib
from typing import Any, Callable

from ..materials.catalogue import preset_rows
from ..materials.section import NAME, ORIGINAL, MaterialSection, section_to_table
from ..resources import builtin_scenes
from ..scene import Scene, SceneError
from ..sim.collision.held_contacts import check_start, held_inputs_differ
from .fabric_panel import FabricPanel
from .panels import Controls


def fabric_name(section: MaterialSection | None) -> str:
    return ORIGINAL if section is None else section.name


def describe_preset(name: str) -> str:
    """"denim (11 oz twill denim, 324 g/m², Wang 2011)"; "original (no fabric)"."""
    for row in preset_rows():
        if row.name == name:
            return f"{name} ({row.kind}, {row.grams_per_m2:.0f} g/m², {row.source})"
    return f"{name} (the unitless sheet, no fabric)" if name == ORIGINAL else name


def names_own_fabric(scene_name: str) -> bool:
    """Whether the built-in scene's file names a fabric of its own (a [material] table or a
    preset). `material = "original"` names none: it says the scene needs no fabric (and
    why, in its comment), so a fabric the user chose is kept there."""
    path = builtin_scenes().get(scene_name)
    if path is None:
        return False
    try:
        own = tomllib.loads(path.read_text("utf-8")).get(NAME)
    except (OSError, UnicodeDecodeError, tomllib.TOMLDecodeError):
        return False
    return own is not None and own != ORIGINAL


class FabricActions:
    """Needs from the app: `scene`, `apply_scene`, `notify`, `release_keys` (key_order.py),
    `controls` and Textual's `screen`."""

    scene: Scene
    own_fabric: MaterialSection | None  # the scene's own, as opened: Restore defaults' fabric
    apply_scene: Callable[..., None]
    notify: Callable[..., None]
    release_keys: Callable[[], None]
    controls: Controls
    screen: Any

    def choose_fabric(self, name: str) -> bool:
        """The sheet in preset `name`, or the original (no fabric). A damping the user set
        stays: a preset has none of its own. Refused (and told) where the scene cannot
        take it, e.g. a solver without compliance."""
        if name == ORIGINAL:
            table: Any = ORIGINAL
        else:
            table = {"preset": name}
            if self.scene.material is not None and "damping" in self.scene.material.table:
                table["damping"] = self.scene.material.table["damping"]
        try:
            new = self.scene.with_value(NAME, table)
            if held_inputs_differ(self.scene, new):
                check_start(new)
        except SceneError as e:
            self.notify(str(e), title="Fabric refused", severity="error", timeout=10)
            self.controls.show_fabric(self.scene)  # the list shows the fabric still on
            return False
        self.apply_scene(new)
        self.notify(f"Fabric: {describe_preset(name)}")
        return True

    def on_fabric_panel_chosen(self, message: FabricPanel.Chosen) -> None:
        """A preset picked in the list: applied, unless it is on already as the preset
        gives it (with no value of the scene's own to set back)."""
        section = self.scene.material
        unchanged = (section is None if message.name == ORIGINAL
                     else section is not None and section.table == {"preset": message.name})
        if not unchanged:
            self.choose_fabric(message.name)

    def on_fabric_panel_changed(self, message: FabricPanel.Changed) -> None:
        """A fabric value typed: applied, or refused with the last good value shown again
        (the field keeps focus for another try); Enter moves on."""
        try:
            if message.table is None:
                raise SceneError(message.problem)
            new = self.scene.with_value(NAME, message.table)
        except SceneError as e:
            self.notify(str(e), title="Value refused", severity="error", timeout=8)
            message.field.show(message.field.last_good)
        else:
            self.apply_scene(new, shown=True)
            self.controls.show_fabric(new)
            if message.submitted:
                self.screen.focus_next()
        if message.submitted:
            self.release_keys()

    def with_fabric_kept(self, scene_name: str, opened: Scene) -> tuple[Scene, str]:
        """The scene opened as `scene_name`, with the fabric now on unless it names its own,
        and a sentence saying which happened."""
        self.own_fabric = opened.material
        current = self.scene.material
        if names_own_fabric(scene_name):
            return opened, f"fabric: {fabric_name(opened.material)}, the scene's own"
        if current is None:
            return opened, f"fabric: {ORIGINAL}"
        try:
            kept = opened.with_value(NAME, section_to_table(current))
        except SceneError as e:
            return opened, f"fabric {current.name} not kept ({e}): {ORIGINAL}"
        return kept, f"fabric {current.name} kept (the scene names none)"

    def restore_defaults(self) -> None:
        """Every key's default, and the scene's own fabric (as it was opened)."""
        new = Scene(name=self.scene.name)
        if self.own_fabric is not None:  # the defaults' solver (hpbd) takes any fabric
            new = new.with_value(NAME, section_to_table(self.own_fabric))
        self.apply_scene(new, restart=True)
        self.notify(f"Settings restored to their defaults; fabric: "
                    f"{fabric_name(new.material)}, the scene's own")
