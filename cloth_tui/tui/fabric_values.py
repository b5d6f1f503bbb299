"""The Fabric group's values as a person reads them: a fabric's numbers in the units textile
data use (g/m², N/m, µN·m, 1/s, mm), converted to and from the `[material]` table's SI keys,
and the validator that checks a typed value in those units. No widgets here.

Each field is declared as a scene key is (scene_keys.key), so the panel's rows are
SettingFields; its range is the material key's (materials.values.KEYS) in the shown unit.
"""

from __future__ import annotations

import dataclasses
import math
from typing import Any

from textual.validation import ValidationResult, Validator

from ..materials.schema import Material
from ..materials.section import MaterialSection
from ..materials.values import KEYS
from ..scene import describe_allowed
from ..scene_keys import key

PREFIX = "fabric."


@dataclasses.dataclass(frozen=True)
class Shown:
    """One shown value: the material key it stands for, its factor from SI to the shown
    unit, and (warp/weft) which entry of `stretch` it is."""
    material_key: str
    factor: float
    unit: str
    entry: int | None = None


SHOWN = {
    "weight": Shown("areal_density", 1000.0, "g/m²"),
    "stretch_warp": Shown("stretch", 1.0, "N/m", entry=0),
    "stretch_weft": Shown("stretch", 1.0, "N/m", entry=1),
    "shear": Shown("shear", 1.0, "N/m"),
    "bending": Shown("bending", 1e6, "µN·m"),
    "damping": Shown("damping", 1.0, "1/s"),
    "tear_strength": Shown("tear_strength", 1.0, "N/m"),
    "tear_length": Shown("tear_length", 1000.0, "mm"),
}
DOCS = {"weight": "areal density (the label's g/m²): the sheet's mass is weight × area",
        "stretch_warp": "tensile stiffness along the warp (x): N per metre of width per "
                        "unit strain",
        "stretch_weft": "tensile stiffness along the weft (z)",
        "tear_strength": "tension per unit width at which the fabric tears, with "
                         "behavior.tear (empty: none; the sheet tears by tear_stretch)",
        "tear_length": "the width across which the tension is averaged before it is "
                       "compared with tear strength: a few yarns (5 mm unless set)"}


def _declare(name: str, shown: Shown) -> tuple[str, str, Any]:
    spec = KEYS[shown.material_key]
    return (name, "float", key(0.0, DOCS.get(name, spec.doc), unit=shown.unit,
                               lo=spec.lo * shown.factor, hi=spec.hi * shown.factor,
                               lo_open=spec.lo_open))


FabricValues = dataclasses.make_dataclass(
    "FabricValues", [_declare(name, shown) for name, shown in SHOWN.items()])
SPECS = {f.name: f for f in dataclasses.fields(FabricValues)}


def dotted(name: str) -> str:
    return PREFIX + name


def shown_value(material: Material, name: str) -> float | str:
    """`material`'s value of field `name` in its shown unit, to 6 significant digits (324,
    not 324.00000000000006); "" for no tear strength."""
    s = SHOWN[name]
    attribute = {"stretch": ("stretch_warp", "stretch_weft")[s.entry or 0]}.get(
        s.material_key, s.material_key)
    value = getattr(material, attribute)
    if value is None:
        return ""
    return float(f"{value * s.factor:.6g}")


class InShownRange(Validator):
    """A typed value of one field, in its shown unit: a finite number within the range the
    material key allows (tear strength may be empty: none)."""

    def __init__(self, name: str) -> None:
        super().__init__()
        self.name = name

    def validate(self, value: str) -> ValidationResult:
        text = value.strip()
        if text == "" and self.name == "tear_strength":
            return self.success()
        spec = SPECS[self.name]
        expected = f"expected {describe_allowed(spec)} ({spec.metadata['unit']})"
        try:
            number = float(text)
        except ValueError:
            return self.failure(f"{self.name.replace('_', ' ')} = {text!r} is not a number; "
                                f"{expected}")
        m = spec.metadata
        if (not math.isfinite(number) or number < m["lo"] or number > m["hi"]
                or (m["lo_open"] and number == m["lo"])):
            return self.failure(f"{self.name.replace('_', ' ')} = {text} is not allowed; "
                                f"{expected}")
        return self.success()


def edited_table(section: MaterialSection, name: str, text: str) -> dict:
    """The `[material]` table after field `name` is set to `text` (checked by
    InShownRange): the keys as given, with this one in SI units; a stretch entry sets
    [warp, weft]; an empty tear strength drops the key."""
    s = SHOWN[name]
    table = dict(section.table)
    if not text.strip():
        table.pop(s.material_key, None)
        return table
    value = float(text) / s.factor
    if s.entry is not None:
        pair = [section.material.stretch_warp, section.material.stretch_weft]
        pair[s.entry] = value
        table["stretch"] = pair
    else:
        table[s.material_key] = value
    return table


def edited_keys(section: MaterialSection) -> list[str]:
    """The fields whose value is the scene's own rather than its preset's."""
    own = set(section.table) - {"preset"}
    return [name for name, s in SHOWN.items() if s.material_key in own]
