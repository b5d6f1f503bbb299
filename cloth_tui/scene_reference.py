"""The README's scene key reference, generated from the key declarations in scene.py."""

from __future__ import annotations

import dataclasses

from .scene import SECTION_TYPES, SECTIONS, SceneObject, describe_allowed
from .scene_files import toml_value


def reference_markdown() -> str:
    """The README's key reference, generated from the declarations in scene.py."""
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
    return "\n".join(rows) + "\n"


def _reference_row(f: dataclasses.Field) -> str:
    default = f.default if f.default is not dataclasses.MISSING else f.default_factory()
    return (f"| `{f.name}` | `{toml_value(default)}` | {f.metadata['unit']} | "
            f"{describe_allowed(f)} | {f.metadata['doc']} |")
