"""The preset table as a person reads it, and what a fabric replaces in a scene.

`preset_rows()`: one row per preset (its name, what kind of fabric it is, its weight in
g/m², where its numbers come from), for the app's Fabric group and palette.
`replaced_keys(material)`: the scene keys of the original's unitless model that a material
takes the place of, each with what stands in for it (model.build_model, params.py and
tearing.py read the material instead). Pure Python, like the rest of the package.
"""

from __future__ import annotations

import re
from dataclasses import dataclass

from .presets import Preset, load_presets
from .schema import Material

# What each measured or estimated row is, from its `note` in presets.toml, in a few words
# (the notes are sentences; the table has no fibre content, only what the fabric is).
KINDS = {
    "wang2011-gray-interlock": "interlock knit (t-shirt)",
    "wang2011-tango-red-jet-set": "polyester jet-set knit",
    "wang2011-camel-ponte-roma": "ponte di roma knit",
    "wang2011-ivory-rib-knit": "rib knit",
    "wang2011-11oz-black-denim": "11 oz twill denim",
    "wang2011-navy-sparkle-sweat": "sweatshirt knit",
    "wang2011-white-swim-solid": "swimwear knit",
    "wang2011-white-dots-on-blk": "tablecloth fabric",
    "wang2011-pink-ribbon-brown": "blanket fabric",
    "wang2011-royal-target": "trousers fabric",
    "cotton": "cotton shirting",
    "silk": "silk habotai",
    "leather": "1 mm garment leather",
}


@dataclass(frozen=True)
class PresetRow:
    name: str
    kind: str            # what the fabric is ("11 oz twill denim")
    grams_per_m2: float  # its areal density in g/m²
    source: str          # "Wang 2011" for a measured row, "estimate" for an estimate
    preset: Preset

    @property
    def is_alias(self) -> bool:
        return bool(self.preset.alias_of)


def short_source(preset: Preset) -> str:
    """"Wang 2011" for "Wang, O'Brien & Ramamoorthi 2011, as distributed with ...";
    "estimate" for an estimate."""
    if preset.estimate:
        return "estimate"
    found = re.match(r"([^\W\d]+)[^0-9]*?(\d{4})", preset.source)
    return f"{found[1]} {found[2]}" if found else preset.source


def preset_rows() -> list[PresetRow]:
    """Every preset: the familiar names (aliases) first, then the estimates, then the
    measured rows under their own names; alphabetical within each."""
    rows = [PresetRow(name=name, kind=KINDS.get(p.alias_of or name, p.note),
                      grams_per_m2=1000.0 * p.areal_density, source=short_source(p),
                      preset=p)
            for name, p in load_presets().items()]
    return sorted(rows, key=lambda r: (not r.is_alias, not r.preset.estimate, r.name))


# Scene key → what takes its place while a material is on.
REPLACED = {
    "cloth.mass": "the fabric's weight × the sheet's area",
    "cloth.mass_model": "the fabric's weight, shared by area",
    "behavior.damping": "the fabric's damping (1/s)",
    "behavior.compliance": "the fabric's stretch, shear and bending",
    "behavior.stiffness": "springs, which take no fabric",
    "behavior.spring_damping": "springs, which take no fabric",
    "behavior.tethers": "none: tethers are no force of the fabric's",
}
REPLACED_WITH_TEAR_STRENGTH = {"behavior.tear_stretch": "the fabric's tear strength (N/m)"}
REPLACEABLE = tuple(REPLACED) + tuple(REPLACED_WITH_TEAR_STRENGTH)


def replaced_keys(material: Material) -> dict[str, str]:
    """Scene key → what takes its place while `material` is on: the keys the simulation
    then does not read."""
    if material.tear_strength is None:
        return dict(REPLACED)
    return {**REPLACED, **REPLACED_WITH_TEAR_STRENGTH}
