"""The measured-fabric table shipped in the package (presets.toml): loading and checking it.

Each row is a fabric in SI units with the source of its numbers, given either as the
physical keys (stretch, shear, bending) or as ARCSim stores a measured fabric
(arcsim_stretching, arcsim_bending), converted here; a row may instead be `alias_of`
another (a familiar name for a measured fabric). Rows marked `estimate = true` are not
measurements and say in `note` how their numbers were chosen.
"""

from __future__ import annotations

import dataclasses
import functools
import importlib.resources
import tomllib
from pathlib import Path

from ..user_values import short_repr
from .errors import MaterialError
from .measured import BendingByDirection, StretchCurve
from .values import number, stretch_pair

PRESET_FILE = "presets.toml"
NUMBERS = ("areal_density", "stretch", "shear", "bending", "tear_strength")
ARCSIM = ("arcsim_stretching", "arcsim_bending")
# The rest of a measured fabric's samples (measured.py): the five stretching samples at strain
# 1/6, and the 45° and 90° hinges' stiffness (both or neither); optional.
ARCSIM_MORE = ("arcsim_stretching_strained", "arcsim_bending_45", "arcsim_bending_90")
ROW_KEYS = NUMBERS + ARCSIM + ARCSIM_MORE + ("source", "note", "estimate", "alias_of")

# What ARCSim (Narain et al. 2012, with Wang et al. 2011's data-driven model) does with a
# stored fabric: it doubles each stretching sample C and uses it on the Green strain G as
# σ = (C11·G00 + C12·G11, ½C33·G01; …), energy ½σ:G per area, so a small strain ε along
# warp stores ½·(2·C11)·ε² and a shear γ (G01 = γ/2) stores ½·(C33/2)·γ²; its hinge energy
# k·l²θ²/(8(A₀+A₁)) is (k/4)/2·κ² per area on a bend, a plate of rigidity k/4.
# tests/materials/test_arcsim.py evaluates those formulas to check the factors.
ARCSIM_STRETCH_FACTOR = 2.0
ARCSIM_SHEAR_FACTOR = 0.5
ARCSIM_BENDING_FACTOR = 0.25


@dataclasses.dataclass(frozen=True)
class Preset:
    name: str
    areal_density: float          # kg/m²
    stretch_warp: float           # N/m
    stretch_weft: float           # N/m
    shear: float                  # N/m
    bending: float                # N·m
    source: str
    estimate: bool = False
    note: str = ""
    tear_strength: float | None = None  # N/m
    alias_of: str = ""            # the measured row this name stands for, "" for a row
    arcsim_stretching: tuple | None = None  # (C11, C12, C22, C33) as stored, if so given
    arcsim_bending: float | None = None     # k as stored, if so given
    stretch_curves: tuple[StretchCurve, StretchCurve] | None = None  # (warp, weft)
    bending_by_direction: BendingByDirection | None = None


def from_arcsim(stretching, bending: float, where: str) -> tuple[float, float, float, float]:
    """(warp, weft, shear, B) of a fabric as ARCSim stores it: [C11, C12, C22, C33] (N/m)
    and its hinge stiffness k (N·m)."""
    if (not isinstance(stretching, list) or len(stretching) != 4
            or any(isinstance(c, bool) or not isinstance(c, (int, float)) for c in stretching)):
        raise MaterialError(f"{where}: arcsim_stretching = {short_repr(stretching)} must be "
                            "[C11, C12, C22, C33], four numbers")
    c11, _, c22, c33 = stretching
    warp = number("stretch", ARCSIM_STRETCH_FACTOR * c11, where)
    weft = number("stretch", ARCSIM_STRETCH_FACTOR * c22, where)
    shear = number("shear", ARCSIM_SHEAR_FACTOR * c33, where)
    if isinstance(bending, bool) or not isinstance(bending, (int, float)):
        raise MaterialError(f"{where}: arcsim_bending = {short_repr(bending)} must be a number")
    return warp, weft, shear, number("bending", ARCSIM_BENDING_FACTOR * bending, where)


def _is_number(v) -> bool:
    return not isinstance(v, bool) and isinstance(v, (int, float))


def measured_curves(row: dict, warp: float, weft: float,
                    where: str) -> tuple[StretchCurve, StretchCurve] | None:
    """(warp, weft) tension curves from the row's strained samples: ARCSim's 0° sample's C11
    and 90° sample's C22, doubled (measured.py)."""
    if "arcsim_stretching_strained" not in row:
        return None
    rows = row["arcsim_stretching_strained"]
    if (not isinstance(rows, list) or len(rows) != 5
            or any(not isinstance(r, list) or len(r) != 4 or not all(map(_is_number, r))
                   for r in rows)):
        raise MaterialError(f"{where}: arcsim_stretching_strained = {short_repr(rows)} must be "
                            "five [C11, C12, C22, C33] (0°, 22.5°, 45°, 67.5°, 90°)")
    high_warp = number("stretch", ARCSIM_STRETCH_FACTOR * rows[0][0], where)
    high_weft = number("stretch", ARCSIM_STRETCH_FACTOR * rows[4][2], where)
    return StretchCurve(warp, high_warp), StretchCurve(weft, high_weft)


def measured_bending(row: dict, bending: float, where: str) -> BendingByDirection | None:
    """The rigidities of folds at 0°, 45° and 90° to the warp (B = k/4 each)."""
    given = [k for k in ("arcsim_bending_45", "arcsim_bending_90") if k in row]
    if not given:
        return None
    if len(given) == 1:
        raise MaterialError(f"{where}: give both arcsim_bending_45 and arcsim_bending_90")
    b45, b90 = (number("bending", ARCSIM_BENDING_FACTOR * row[k], where)
                if _is_number(row[k]) else None for k in given)
    if b45 is None or b90 is None:
        raise MaterialError(f"{where}: arcsim_bending_45 and arcsim_bending_90 must be numbers")
    found = BendingByDirection(bending, b45, b90)
    if found.grid_rigidities()[2] <= 0.0:
        raise MaterialError(f"{where}: a 45° rigidity {b45:.3g} N·m at or below a quarter of "
                            f"0° and 90° together ({bending:.3g} + {b90:.3g}) has no convex "
                            "bending energy on the grid")
    return found


def parse_presets(text: str, where: str = PRESET_FILE) -> dict[str, Preset]:
    """The table in `text` (TOML), every row checked; aliases resolved to their row."""
    try:
        doc = tomllib.loads(text)
    except tomllib.TOMLDecodeError as e:
        raise MaterialError(f"{where}: not valid TOML: {e}") from None
    rows, aliases = {}, {}
    for name, row in doc.items():
        here = f"{where}: [{name}]"
        if not isinstance(row, dict):
            raise MaterialError(f"{here} must be a table")
        unknown = [k for k in row if k not in ROW_KEYS]
        if unknown:
            raise MaterialError(f"{here}: unknown key {unknown[0]!r}; a row has "
                                f"{', '.join(ROW_KEYS)}")
        if "alias_of" in row:
            if len(row) != 1 or not isinstance(row["alias_of"], str):
                raise MaterialError(f"{here}: an alias has only alias_of = \"ROW\"")
            aliases[name] = row["alias_of"]
            continue
        arcsim = any(k in row for k in ARCSIM)
        given = ("areal_density",) + (ARCSIM if arcsim else ("stretch", "shear", "bending"))
        if arcsim and any(k in row for k in ("stretch", "shear", "bending")):
            raise MaterialError(f"{here}: give stretch, shear and bending or arcsim_stretching "
                                "and arcsim_bending, not both")
        missing = [k for k in given + ("source",) if k not in row]
        if missing:
            raise MaterialError(f"{here} lacks {', '.join(missing)}")
        for k in ("source", "note"):
            if k in row and not (isinstance(row[k], str) and row[k].strip()):
                raise MaterialError(f"{here}: {k} = {short_repr(row[k])} must be a "
                                    "non-empty string")
        estimate = row.get("estimate", False)
        if not isinstance(estimate, bool):
            raise MaterialError(f"{here}: estimate must be true or false")
        if estimate and not row.get("note"):
            raise MaterialError(f"{here}: an estimate must say in `note` how it was made")
        if not arcsim and any(k in row for k in ARCSIM_MORE):
            raise MaterialError(f"{here}: {', '.join(ARCSIM_MORE)} need arcsim_stretching "
                                "and arcsim_bending")
        curves = directions = None
        if arcsim:
            warp, weft, shear, bending = from_arcsim(row["arcsim_stretching"],
                                                     row["arcsim_bending"], here)
            curves = measured_curves(row, warp, weft, here)
            directions = measured_bending(row, bending, here)
        else:
            warp, weft = stretch_pair(row["stretch"], here)
            shear = number("shear", row["shear"], here)
            bending = number("bending", row["bending"], here)
        rows[name] = Preset(
            name=name, areal_density=number("areal_density", row["areal_density"], here),
            stretch_warp=warp, stretch_weft=weft, shear=shear, bending=bending,
            source=row["source"], estimate=estimate, note=row.get("note", ""),
            tear_strength=(number("tear_strength", row["tear_strength"], here)
                           if "tear_strength" in row else None),
            arcsim_stretching=tuple(row["arcsim_stretching"]) if arcsim else None,
            arcsim_bending=row["arcsim_bending"] if arcsim else None,
            stretch_curves=curves, bending_by_direction=directions)
    for name, target in aliases.items():
        if target not in rows:
            raise MaterialError(f"{where}: [{name}] is alias_of {target!r}, which is not a "
                                "row of the table")
        rows[name] = dataclasses.replace(rows[target], name=name, alias_of=target)
    return dict(sorted(rows.items()))


@functools.cache
def load_presets() -> dict[str, Preset]:
    """The package's table, read once."""
    text = importlib.resources.files(__package__).joinpath(PRESET_FILE).read_text("utf-8")
    return parse_presets(text)


def load_preset_file(path: str | Path) -> dict[str, Preset]:
    """A table of the same form from a file of the user's."""
    try:
        text = Path(path).read_text("utf-8")
    except (OSError, UnicodeDecodeError) as e:
        raise MaterialError(f"cannot read {path}: {getattr(e, 'strerror', None) or e}") \
            from None
    return parse_presets(text, str(path))


def preset_names() -> list[str]:
    return list(load_presets())


def get_preset(name: str, where: str = "material") -> Preset:
    presets = load_presets()
    if name not in presets:
        raise MaterialError(f"{where}.preset = {short_repr(name)} is not a preset; the "
                            f"presets are {', '.join(presets)}")
    return presets[name]
