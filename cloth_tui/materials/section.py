"""The scene's `[material]` section: how a scene file, a `--set` override and the app give a
scene its fabric (scene.py hooks these in; schema.py checks the keys themselves).

In a scene file the fabric is either a table,

    [material]
    preset = "denim"
    damping = 0.5

or `material = "original"`, which is the same as no section: the original's unitless
solver keys (behavior.compliance, cloth.mass, behavior.damping, ...) and today's numbers.
A `--set material.KEY=VALUE` changes one key of the table (a new preset keeps the keys
given beside it); `--set material=original` drops the table. The section keeps the keys as
given, so that a scene saved again says what its author wrote, not every value a preset
filled in. Pure Python, like scene.py; errors are MaterialError, which scene.py turns into
its SceneError.
"""

from __future__ import annotations

from dataclasses import dataclass
from typing import Any

from .. import solver_specs as solver_registry
from ..user_values import short_repr
from .errors import MaterialError
from .schema import ALL_KEYS, Material, material_from_table

ORIGINAL = "original"
NAME = "material"


@dataclass(frozen=True)
class MaterialSection:
    table: dict           # the keys as given (file, overrides), checked
    material: Material    # what they describe, presets resolved

    @property
    def name(self) -> str:
        """How the status line and messages name the fabric."""
        return self.material.preset or "custom"


def section_from_value(value: Any) -> MaterialSection | None:
    """The section of a scene document's `material` value: a table, or the string
    "original" (None: no material)."""
    if isinstance(value, str):
        if value != ORIGINAL:
            raise MaterialError(f"{NAME} = {short_repr(value)} is not allowed: write "
                                f"{NAME} = \"{ORIGINAL}\" or a [{NAME}] table (e.g. "
                                f"preset = {short_repr(value)})")
        return None
    if not isinstance(value, dict):
        raise MaterialError(f"[{NAME}] must be a table or {NAME} = \"{ORIGINAL}\", got "
                            f"{type(value).__name__}")
    if value.get("preset") == ORIGINAL:
        if len(value) > 1:
            raise MaterialError(f"{NAME}.preset = \"{ORIGINAL}\" is the original's unitless "
                                f"solver and takes no other [{NAME}] keys; drop "
                                f"{', '.join(k for k in value if k != 'preset')}")
        return None
    table = dict(value)
    return MaterialSection(table=table, material=material_from_table(table, NAME))


def is_material_key(dotted: str) -> bool:
    """Whether an override names the material: `material` or `material.KEY`."""
    return dotted == NAME or dotted.startswith(NAME + ".")


def with_material_key(section: MaterialSection | None, dotted: str,
                      value: Any) -> MaterialSection | None:
    """The section after one override: `material` = a table or "original", or
    `material.KEY` = a value (a new preset keeps the other keys given)."""
    if dotted == NAME:
        return section_from_value(value)
    key = dotted[len(NAME) + 1:]
    if key not in ALL_KEYS:
        raise MaterialError(f"unknown key {dotted!r}: [{NAME}] has {', '.join(ALL_KEYS)}")
    table = dict(section.table) if section is not None else {}
    table[key] = value
    if key == "preset" and value == ORIGINAL:
        table = {"preset": ORIGINAL}
    return section_from_value(table)


def section_to_table(section: MaterialSection) -> dict:
    """The table to write back to a scene file."""
    return dict(section.table)


def solver_problem(section: MaterialSection | None, solver: str) -> str | None:
    """Why the scene's solver cannot simulate its material, or None."""
    able = solver_registry.names(takes_material=True)
    if section is None or solver in able:
        return None
    quoted = " or ".join(f'"{n}"' for n in able)
    return (f"[{NAME}] ({section.name}) needs behavior.solver = {quoted}, whose "
            f"constraints take the material's "
            f"compliance; {solver} has none (or write {NAME} = \"{ORIGINAL}\" for the "
            f"original's unitless keys)")
