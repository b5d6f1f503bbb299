"""The `[material]` section: what each key means, its unit and range, and its validation.

A material is the fabric in SI units, independent of the grid that discretises it:

- `preset`: a row of the measured-fabric table (presets.toml); the other keys override it.
- `areal_density` (kg/m²): mass per unit area; the sheet's mass is density × area.
- `stretch` (N/m): the membrane's tensile stiffness, tension per unit width per unit strain,
  one number or [warp, weft] (warp along the grid's x, weft along its z).
- `shear` (N/m): in-plane shear stiffness, shear force per unit length per radian of shear.
- `bending` (N·m): the bending rigidity B, moment per unit width per unit curvature; one
  number, or [warp, weft]: the rigidities of a strip cut along the warp (bending along x)
  and of one cut along the weft (along z), the two ASTM D1388 measures. A pair bends by
  direction as a measured preset does (measured.BendingByDirection.of_strips gives its
  bias), and `Material.bending` is then the weft's, a preset's fold along the warp.
- `damping` (1/s): a viscous drag per unit mass: without other forces a velocity decays as
  exp(−damping·t), whatever the timestep and substeps (0.69/s halves it each second).
- `tear_strength` (N/m, optional): tension per unit width at which the fabric tears.
- `tear_length` (m, default 5 mm): the width across which the tension is averaged before it is
  compared with tear_strength, so that where stress concentrates (the end of a clamped line)
  the outcome converges as the grid refines (sim/tearing.py).

A measured preset also brings its stretch that stiffens with strain and its bending by
direction (measured.py), which `stretch` and `bending` above give at small strain and for a
fold along the warp; a `stretch` or `bending` typed beside the preset replaces them with the
linear model of that number (a bending pair: with its own directions).

Pure Python: the scene loader will call `material_from_table` and turn a MaterialError into
its SceneError (this module cannot import scene.py, which will import it).
"""

from __future__ import annotations

import math
from dataclasses import dataclass
from typing import Any

from ..user_values import short_repr
from .errors import MaterialError
from .measured import BendingByDirection, StretchCurve
from .presets import get_preset, preset_names
from .values import DEFAULT_TEAR_LENGTH, KEYS, bending_pair, number, stretch_pair

ALL_KEYS = ("preset",) + tuple(KEYS)
NEEDED_WITHOUT_PRESET = ("areal_density", "stretch", "shear", "bending")


@dataclass(frozen=True)
class Material:
    areal_density: float           # kg/m²
    stretch_warp: float            # N/m, along the grid's x (columns)
    stretch_weft: float            # N/m, along the grid's z (rows)
    shear: float                   # N/m per radian of shear
    bending: float                 # N·m
    damping: float = 0.0           # 1/s
    tear_strength: float | None = None  # N/m
    tear_length: float = DEFAULT_TEAR_LENGTH  # m, the width tear_strength is judged over
    preset: str = ""               # the preset it started from, "" for none
    # A measured preset's (warp, weft) tension curves and fold rigidities by direction; None:
    # the linear stretch and the one bending rigidity above.
    stretch_curves: tuple[StretchCurve, StretchCurve] | None = None
    bending_by_direction: BendingByDirection | None = None


def material_from_table(table: Any, where: str = "material") -> Material:
    """Validate a `[material]` table (as parsed from TOML or built from `--set` values) and
    return the Material it describes. Raises MaterialError naming the key and what is
    allowed."""
    if not isinstance(table, dict):
        raise MaterialError(f"[{where}] must be a table, got {type(table).__name__}")
    unknown = [k for k in table if k not in ALL_KEYS]
    if unknown:
        raise MaterialError(f"unknown key {where}.{unknown[0]}: [{where}] has "
                            f"{', '.join(ALL_KEYS)}")
    values: dict[str, Any] = {}
    preset_name = ""
    curves = directions = None
    if "preset" in table:
        preset_name = table["preset"]
        if not isinstance(preset_name, str):
            raise MaterialError(f"{where}.preset = {short_repr(preset_name)} is not allowed; "
                                f"expected one of {', '.join(preset_names())}")
        p = get_preset(preset_name, where)
        values = dict(areal_density=p.areal_density, stretch=(p.stretch_warp, p.stretch_weft),
                      shear=p.shear, bending=p.bending, tear_strength=p.tear_strength)
        curves = None if "stretch" in table else p.stretch_curves
        directions = None if "bending" in table else p.bending_by_direction
    else:
        missing = [k for k in NEEDED_WITHOUT_PRESET if k not in table]
        if missing:
            raise MaterialError(f"[{where}] without a preset needs "
                                f"{', '.join(NEEDED_WITHOUT_PRESET)} (missing: "
                                f"{', '.join(missing)}); or set {where}.preset")
    for name in KEYS:
        if name not in table:
            continue
        if name == "stretch":
            values[name] = stretch_pair(table[name], where)
        elif name == "bending" and (pair := bending_pair(table[name], where)) is not None:
            directions = BendingByDirection.of_strips(*pair)
            values[name] = directions.fold_0
        else:
            values[name] = number(name, table[name], where)
    warp, weft = values["stretch"]
    return Material(areal_density=values["areal_density"], stretch_warp=warp,
                    stretch_weft=weft, shear=values["shear"], bending=values["bending"],
                    damping=values.get("damping", 0.0),
                    tear_strength=values.get("tear_strength"),
                    tear_length=values.get("tear_length", DEFAULT_TEAR_LENGTH),
                    preset=preset_name,
                    stretch_curves=curves, bending_by_direction=directions)


def stiffness_at_tension(material: Material, tension: float) -> float:
    """N/m: the larger of the warp's and weft's stiffness dT/dε where each pulls with
    `tension` (N/m): the stretch itself for the linear model, the tension curve's tangent
    for a measured preset's (what an error in strain costs in tension there)."""
    if material.stretch_curves is None:
        return max(material.stretch_warp, material.stretch_weft)
    return max(c.tangent(c.strain_at(tension)) for c in material.stretch_curves)


def bending_length(material: Material, gravity: float = 9.81) -> float:
    """Peirce's bending length c = (B / (ρ_A g))^⅓ in metres: the fabric's own scale, half
    the overhang of the ASTM D1388 cantilever test."""
    return math.cbrt(material.bending / (material.areal_density * gravity))


def strip_rigidities(material: Material) -> tuple[float, float]:
    """N·m: (warp, weft), the bending rigidity of a strip cut along the warp (curving along
    x) and of one cut along the weft (along z); the one rigidity twice without directions."""
    d = material.bending_by_direction
    if d is None:
        return material.bending, material.bending
    return d.fold_90, d.fold_0

