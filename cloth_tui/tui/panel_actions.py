"""What the control panels, the help and the layout ask of the app: a field edited, the objects or
pin groups changed, a panel button, the controls drawer, the help screen, and a digit typed with no
field focused. A mixin of `ClothApp`, which owns the scene and applies it."""

from __future__ import annotations

from typing import Any, Callable

from textual import events
from textual.screen import Screen
from textual.widget import Widget

from ..scene import Scene, SceneError
from ..sim.collision.held_contacts import check_start, held_inputs_differ
from .help import HelpScreen
from .panels import Controls, ObjectsPanel, SettingField
from .pins_panel import PinsPanel
from .view_actions import typed_digit_notice

WIDE_FROM = 120  # columns; below, the controls are a drawer and the status line is compact
NARROW_CLASS = "-narrow"
WIDE_CLASS = "-wide"


class PanelActions:
    """Needs from the app: `scene`, `set_value`, `apply_scene`, `action_restart`, `notify`,
    `recent_view_keys`, `release_keys` (key_order.py), and Textual's `screen`, `focused`,
    `query_one`, `push_screen` and `pop_screen`."""

    scene: Scene
    set_value: Callable[[str, Any], bool]
    apply_scene: Callable[..., None]
    action_restart: Callable[[], None]
    restore_defaults: Callable[[], None]
    notify: Callable[..., None]
    recent_view_keys: Callable[[], list[str]]
    release_keys: Callable[[], None]
    screen: Screen
    focused: Widget | None
    query_one: Callable[..., Widget]
    push_screen: Callable[..., Any]
    pop_screen: Callable[[], Any]

    def on_setting_field_edited(self, message: SettingField.Edited) -> None:
        self._settle_edit(message)
        if message.submitted:
            self.release_keys()  # the keys typed after Enter, now that focus is settled

    def _settle_edit(self, message: SettingField.Edited) -> None:
        dotted = message.dotted
        if message.value != self.scene.get(dotted) and not self.set_value(dotted, message.value):
            message.field.show(self.scene.get(dotted))
            return  # refused: the field keeps focus for another try
        message.field.show(self.scene.get(dotted))  # canonical text, e.g. "1.0" → "1"
        if message.submitted:
            self.screen.focus_next()  # Enter: on to the next field

    def on_objects_panel_changed(self, message: ObjectsPanel.Changed) -> None:
        # check_start: an object over a pinned particle is refused here, not by the sim
        self._settle_list(message, lambda: self.scene.with_objects(message.objects),
                          "Object refused",
                          lambda new: self.query_one(ObjectsPanel).show_objects(new.objects))

    def on_pins_panel_changed(self, message: PinsPanel.Changed) -> None:
        # check_start: groups that disagree, or a held particle inside an object
        self._settle_list(message, lambda: self.scene.with_pins(message.pins),
                          "Pin group refused",
                          lambda new: self.query_one(PinsPanel).show_pins(new.pins))

    def _settle_list(self, message, build, refused: str, show: Callable[[Scene], None]
                     ) -> None:
        """Apply a list panel's edit, or refuse it and show the field's last good value; on
        Enter, move on and let the keys typed after it through. `show` shows the new list
        in its panel (nothing else changed)."""
        try:
            new = build()
            if held_inputs_differ(self.scene, new):
                check_start(new)
        except SceneError as e:
            self.notify(str(e), title=refused, severity="error", timeout=8)
            if message.field is not None:
                message.field.show(message.field.last_good)
        else:
            self.apply_scene(new, shown=True)
            show(new)
            if message.submitted:
                self.screen.focus_next()
        if message.submitted:
            self.release_keys()

    def on_controls_command(self, message: Controls.Command) -> None:
        if message.command == "restart":
            self.action_restart()
        elif message.command == "defaults":
            self.restore_defaults()  # fabric_actions.py: with the scene's own fabric
        elif message.command == "hide":
            self.action_toggle_controls()

    def on_key(self, event: events.Key) -> None:
        """A digit typed with no field focused was meant for a field: say so, and what the
        view keys typed with it (`.` `,` `-` `+`) did, rather than orbit in silence."""
        if event.character and event.character.isdigit() and self.focused is None:
            self.notify(typed_digit_notice(event.character, self.recent_view_keys()),
                        severity="warning", timeout=4)

    def action_toggle_controls(self) -> None:
        """Hide or show the side panel; on a narrow screen, open or close the drawer."""
        narrow = self.screen.has_class(NARROW_CLASS)
        self.query_one("#main").toggle_class("-drawer-open" if narrow else "-controls-hidden")

    def action_help(self) -> None:
        if isinstance(self.screen, HelpScreen):
            self.pop_screen()
        else:
            self.push_screen(HelpScreen())
