"""Regenerate the key reference at the end of docs/scene-keys.md from the declarations in
scene.py (`cloth_tui.scene_reference.reference_markdown()`); tests/test_scene.py checks that
the page holds what this writes.

    python tools/scene_keys_page.py
"""

from __future__ import annotations

import sys
from pathlib import Path

sys.path.insert(0, str(Path(__file__).resolve().parent.parent))

from cloth_tui.scene_reference import reference_markdown  # noqa: E402

PAGE = Path(__file__).resolve().parent.parent / "docs" / "scene-keys.md"
MARKER = "<!-- generated from cloth_tui/scene.py by cloth_tui.scene_reference"


def main() -> int:
    text = PAGE.read_text(encoding="utf-8")
    if text.count(MARKER) != 1:
        print(f"scene_keys_page: {PAGE} has no single generated-reference marker", file=sys.stderr)
        return 2
    head, rest = text.split(MARKER, 1)
    marker_line = MARKER + rest.split("\n", 1)[0]
    tmp = PAGE.with_name(f".{PAGE.name}.tmp")
    tmp.write_text(f"{head}{marker_line}\n{reference_markdown()}", encoding="utf-8")
    tmp.replace(PAGE)
    print(f"updated {PAGE}")
    return 0


if __name__ == "__main__":
    sys.exit(main())
