"""The help screen (`?`, F1): every key and mouse action by group. The keys are read from the
bindings themselves (the app's groups, the fields' and Textual's focus keys), so the list
cannot drift from what the keys do."""

from __future__ import annotations

from rich.table import Table
from rich.text import Text
from textual.app import App, ComposeResult
from textual.binding import Binding
from textual.containers import VerticalScroll
from textual.screen import ModalScreen, Screen
from textual.widgets import Input, Static, Switch

from .bindings import KEY_GROUPS, MOUSE_ACTIONS
from .setting_field import SettingField

# What the field keys do in this app (their bindings' own words are Textual's generic ones).
FIELD_ACTIONS = {
    "app.focus_next": "next control",
    "app.focus_previous": "previous control",
    "submit": "apply the value and move to the next field",
    "toggle_switch": "toggle a focused switch",
}
KEY_WIDTH_AT_MOST = 26
FABRIC_ROWS = [
    ("Controls: Fabric", "the fabric's presets (name, weight in g/m², what it is, its "
                         "source) and \"original\", the unitless sheet: ↑ ↓ and Enter, or a "
                         "click, picks one"),
    ("its values", "weight g/m², stretch warp and weft N/m, shear N/m, bending µN·m, "
                   "damping 1/s, tear strength N/m, tear length mm: edited as any field"),
    ("with a fabric on", "mass, compliance, damping and the springs' keys say \"by the "
                         "fabric\": it replaces them; opening another scene keeps it unless "
                         "that scene names its own; Restore defaults gives the scene's own"),
]  # the keys' column: as wide as its widest entry, up to this


def field_bindings() -> list[Binding]:
    """The keys of the controls: focus moves, Enter in a field, a switch's keys, and the
    field's own (SettingField's)."""
    found = [b for cls in (Screen, Input, Switch) for b in cls.BINDINGS
             if isinstance(b, Binding) and b.action in FIELD_ACTIONS]
    return found + [b for b in SettingField.BINDINGS if isinstance(b, Binding)]


def key_text(app: App, binding: Binding) -> str:
    """Every key of a binding ("+ / =", "h / shift+←"), as the footer would show each."""
    keys = [k.strip() for k in binding.key.split(",")]
    return " / ".join(app.get_key_display(Binding(k, binding.action)) for k in keys)


def help_groups(app: App) -> dict[str, list[tuple[str, str]]]:
    """Group title → (keys, what they do) rows."""
    groups = {name: [(key_text(app, b), b.tooltip or b.description) for b in bindings]
              for name, bindings in KEY_GROUPS.items()}
    groups["Fields"] = [(key_text(app, b), FIELD_ACTIONS.get(b.action, b.tooltip or
                                                             b.description))
                        for b in field_bindings()]
    palette = Binding(app.COMMAND_PALETTE_BINDING, "command_palette")
    groups["Fields"].append((key_text(app, palette), "command palette: open a built-in scene, "
                             "or pick a fabric (type its name: \"denim\")"))
    groups["Fabric"] = FABRIC_ROWS
    groups["Mouse"] = list(MOUSE_ACTIONS)
    return groups


def help_table(app: App) -> Table:
    """Plain text cells (no markup: `[` is a key here), wrapped within their column."""
    groups = help_groups(app)
    widest = max(len(keys) for rows in groups.values() for keys, _ in rows)
    table = Table(box=None, show_header=False, padding=(0, 1), expand=True)
    table.add_column(width=min(widest, KEY_WIDTH_AT_MOST), style="bold", overflow="fold")
    table.add_column(ratio=1)
    for name, rows in groups.items():
        table.add_row(Text(name, style="bold underline"), "")
        for keys, what in rows:
            table.add_row(Text(keys), Text(what))
        table.add_row("", "")
    return table


class HelpScreen(ModalScreen[None]):
    """Keys and mouse actions; Escape, ? or F1 closes it. The list has the focus, so its
    own keys scroll it (arrows, PageUp/PageDown, Home/End); j, k and space too."""

    DEFAULT_CSS = """
    HelpScreen { align: center middle; }
    HelpScreen #help { width: 90; max-width: 100%; height: auto; max-height: 100%;
                       border: round $accent; background: $panel; padding: 0 1; }
    """
    BINDINGS = [Binding("escape", "close", "Close help"),  # ? and F1: the app's help key
                Binding("j", "scroll('down')", "Scroll down", show=False),
                Binding("k", "scroll('up')", "Scroll up", show=False),
                Binding("space", "scroll('page_down')", "Page down", show=False)]

    def compose(self) -> ComposeResult:
        with VerticalScroll(id="help") as box:
            box.border_title = "cloth-tui keys (↑ ↓ PgUp PgDn scroll · Escape closes)"
            yield Static(help_table(self.app), id="help-text")

    def on_mount(self) -> None:
        self.query_one("#help", VerticalScroll).focus()

    def action_scroll(self, how: str) -> None:
        """`how`: down, up or page_down (the list's own scroll_… methods)."""
        getattr(self.query_one("#help", VerticalScroll), f"scroll_{how}")()

    def action_close(self) -> None:
        self.dismiss()
