"""The Fabric group: the list of presets (name, what the fabric is, its weight, where its
numbers come from), "original" (the unitless sheet, no fabric) first, and the chosen
fabric's values in the units textile data use (fabric_values.py), edited as any other
field. The panel never changes the scene: it posts `Chosen` or `Changed` and the app
decides (and may refuse, restoring the shown value)."""

from __future__ import annotations

from rich.text import Text
from textual.app import ComposeResult
from textual.containers import Vertical
from textual.message import Message
from textual.widgets import Input, Label, OptionList
from textual.widgets.option_list import Option

from ..materials.catalogue import PresetRow, preset_rows
from ..materials.schema import Material
from ..materials.section import ORIGINAL, MaterialSection
from .fabric_values import (SHOWN, SPECS, InShownRange, dotted, edited_keys, edited_table,
                            shown_value)
from .setting_field import SettingField, format_value, widget_id

LIST_ID = "fabric-presets"


def preset_prompt(row: PresetRow | None) -> Text:
    """Two lines: the name and its weight; what the fabric is and its source (dim)."""
    if row is None:
        return Text.assemble((ORIGINAL, "bold"), "\n",
                             ("  the unitless sheet: no fabric", "dim"))
    return Text.assemble((row.name, "bold"), f"  {row.grams_per_m2:.0f} g/m²", "\n",
                         (f"  {row.kind} · {row.source}", "dim"))


def fabric_title(section: MaterialSection | None) -> str:
    """"fabric: denim" (with the values the scene sets itself), or the original."""
    if section is None:
        return f"[b]fabric:[/] {ORIGINAL} [dim](no fabric: mass, compliance and damping " \
               "are the Scene and Behavior keys)[/]"
    own = edited_keys(section)
    edited = f" [dim]({', '.join(k.replace('_', ' ') for k in own)} set here)[/]" if own else ""
    return f"[b]fabric:[/] {section.name}{edited}"


def measured_note(material: Material) -> str:
    """What a measured preset has beyond the values shown (materials/measured.py): stretch
    that stiffens with strain, bending by direction; "" for a linear fabric."""
    parts, shown = [], []
    if material.stretch_curves is not None:
        warp, weft = material.stretch_curves
        parts.append(f"stretch stiffens with strain (warp {warp.low:.3g} → {warp.high:.3g}, "
                     f"weft {weft.low:.4g} → {weft.high:.4g} N/m by {100 * warp.reach:.0f} %)")
        shown.append("small-strain stretch")
    if material.bending_by_direction is not None:
        b = material.bending_by_direction
        parts.append(f"bending by fold 0°/45°/90°: {1e6 * b.fold_0:.3g} / {1e6 * b.fold_45:.3g}"
                     f" / {1e6 * b.fold_90:.3g} µN·m")
        shown.append("0° bending")
    if not parts:
        return ""
    return (f"[dim]measured: {'; '.join(parts)}. Below: {', '.join(shown)}; typing one "
            "makes it linear.[/]")


class FabricPanel(Vertical):
    """Pick a fabric from the list (↑ ↓ Enter, or a click) and edit its values."""

    DEFAULT_CSS = """
    FabricPanel { height: auto; }
    FabricPanel #fabric-title { width: 1fr; height: auto; margin-bottom: 1; }
    FabricPanel #fabric-presets { height: 12; margin-bottom: 1; padding: 0; }
    FabricPanel.-original #fabric-values { display: none; }
    FabricPanel #fabric-values { height: auto; }
    FabricPanel #fabric-measured { width: 1fr; height: auto; margin-bottom: 1; }
    """

    class Chosen(Message):
        """Posted when the user picks an entry of the preset list: `name` is a preset's
        name or "original" (no fabric)."""

        def __init__(self, name: str) -> None:
            super().__init__()
            self.name = name

    class Changed(Message):
        """Posted when the user submits (Enter) or leaves a fabric value: `table` is the
        whole `[material]` table that value asks for, or None where the typed text is
        refused (`problem` says why, in the shown unit); `field` is the row edited, to
        show its last good value if refused; `submitted`: Enter in that row."""

        def __init__(self, table: dict | None, field: SettingField, submitted: bool,
                     problem: str = "") -> None:
            super().__init__()
            self.table, self.field, self.submitted = table, field, submitted
            self.problem = problem

    def __init__(self, section: MaterialSection | None, *, id: str | None = None) -> None:
        super().__init__(id=id)
        self._section = section
        self._rows = preset_rows()

    def compose(self) -> ComposeResult:
        yield Label(fabric_title(self._section), id="fabric-title")
        options = [Option(preset_prompt(None), id=ORIGINAL)]
        options += [Option(preset_prompt(row), id=row.name) for row in self._rows]
        yield OptionList(*options, id=LIST_ID)
        with Vertical(id="fabric-values"):
            yield Label("", id="fabric-measured")
            for name in SHOWN:
                value = shown_value(self._section.material, name) if self._section else 0.0
                yield SettingField(dotted(name), value, spec=SPECS[name])

    def on_mount(self) -> None:
        tear = self.query_one("#" + widget_id(dotted("tear_strength")), Input)
        tear.placeholder = "none"  # the tooltip says it then tears by tear_stretch
        self.show_fabric(self._section)

    def show_fabric(self, section: MaterialSection | None) -> None:
        """Show `section`'s fabric (None: the original): its name, its entry highlighted in
        the list, its values."""
        self._section = section
        self.set_class(section is None, "-original")
        self.query_one("#fabric-title", Label).update(fabric_title(section))
        presets = self.query_one(OptionList)
        name = ORIGINAL if section is None else section.material.preset
        if name:
            presets.highlighted = presets.get_option_index(name)
        if section is None:
            return
        note = self.query_one("#fabric-measured", Label)
        note.update(measured_note(section.material))
        note.display = bool(measured_note(section.material))
        for field in self.query(SettingField):
            field.show(shown_value(section.material, field.dotted.split(".", 1)[1]))

    def on_option_list_option_selected(self, event: OptionList.OptionSelected) -> None:
        event.stop()
        self.post_message(self.Chosen(event.option.id or ORIGINAL))

    def on_setting_field_edited(self, event: SettingField.Edited) -> None:
        event.stop()
        name = event.dotted.split(".", 1)[1]
        text = event.value if isinstance(event.value, str) else format_value(event.value)
        result = InShownRange(name).validate(text)
        if not result.is_valid or self._section is None:
            problem = "; ".join(result.failure_descriptions) or "no fabric is chosen"
            self.post_message(self.Changed(None, event.field, event.submitted, problem))
            return
        table = edited_table(self._section, name, text)
        self.post_message(self.Changed(table, event.field, event.submitted))
