"""docs/scene-keys.md's key reference, generated from the key declarations in scene.py."""

from __future__ import annotations

import dataclasses

from .materials.presets import preset_names
from .materials.values import KEYS, describe
from .pin_groups import ALLOWED, PinGroup
from .scene import SECTION_TYPES, SECTIONS, SceneObject, describe_allowed
from .scene_files import toml_value
from .sim.solvers.registry import DEFAULT as DEFAULT_SOLVER
from .sim.solvers.registry import names as solver_names


def material_solvers() -> tuple[str, ...]:
    return solver_names(takes_material=True)


def reference_markdown() -> str:
    """docs/scene-keys.md's key reference, generated from the declarations in scene.py."""
    rows = []
    for s in SECTIONS:
        rows += [f"\n### [{s}]\n", "| key | default | unit | allowed | meaning |",
                 "|---|---|---|---|---|"]
        for f in dataclasses.fields(SECTION_TYPES[s]):
            rows.append(_reference_row(f))
    rows += ["\n### [[objects]]\n",
             "Each `[[objects]]` table adds one object (a custom scene with several objects).\n",
             "| key | default | unit | allowed | meaning |", "|---|---|---|---|---|"]
    rows += [_reference_row(f) for f in dataclasses.fields(SceneObject)]
    rows += ["\n### [[pins]]\n",
             "Each `[[pins]]` table holds a group of particles (see [Pin groups](#pin-groups); "
             "with `--set`, `pins=[{...}, ...]` sets the whole array).\n",
             "| key | default | unit | allowed | meaning |", "|---|---|---|---|---|"]
    rows += [_reference_row(f, ALLOWED[f.name]) for f in dataclasses.fields(PinGroup)]
    rows += ["\n### [material]\n",
             "The fabric in SI units (see [Materials in SI units]"
             "(physics.md#materials-in-si-units--material); it needs a `behavior.solver` that "
             "takes one: " + ", ".join(f'`"{name}"`' for name in material_solvers())
             + f" (the default is `\"{DEFAULT_SOLVER}\"`)). `material = \"original\"`, or no "
             "section, keeps the original's unitless keys. Without `preset`, areal_density, "
             "stretch, shear and bending are "
             "all needed; with it, the keys given override the preset's.\n",
             "| key | default | unit | allowed | meaning |", "|---|---|---|---|---|",
             f"| `preset` | (none) |  | a name of the measured-fabric table "
             f"({', '.join(preset_names())}) | the fabric the other keys start from |"]
    for name, spec in KEYS.items():
        default = "`0.0`" if name == "damping" else "(none)" if name == "tear_strength" \
            else "(the preset's)"
        rows.append(f"| `{name}` | {default} | {spec.unit} | {describe(name)} | {spec.doc} |")
    return "\n".join(rows) + "\n"


def _reference_row(f: dataclasses.Field, allowed: str | None = None) -> str:
    default = f.default if f.default is not dataclasses.MISSING else f.default_factory()
    shown = "(all)" if f.name in ("rows", "cols") else "(none)" if default == [] else \
        f"`{toml_value(default)}`"
    return (f"| `{f.name}` | {shown} | {f.metadata['unit']} | "
            f"{allowed or describe_allowed(f)} | {f.metadata['doc']} |")
