"""The private Textual and Rich names the app uses are all reached through
tui/textual_adapter.py: they are there in the installed versions (an upgrade that moves one
fails here), and no other module of the package imports or touches them."""

import ast
from pathlib import Path

import cloth_tui
from cloth_tui.tui import textual_adapter

ADAPTER = Path(textual_adapter.__file__)
# The private attributes the adapter reads on Textual's and Rich's objects.
ADAPTED_ATTRIBUTES = {"_driver", "_compositor", "_color_system"}


def test_every_private_name_the_app_uses_is_where_the_adapter_looks():
    assert textual_adapter.missing_private_names() == []


def test_the_check_sees_a_private_name_that_moved(monkeypatch):
    monkeypatch.delattr("rich._palettes.STANDARD_PALETTE")
    assert textual_adapter.missing_private_names() == ["rich._palettes.STANDARD_PALETTE[0..15]"]


def test_the_adapter_reaches_them():
    from rich.console import Console
    from textual.app import App
    from textual.widgets import Input

    console = Console(force_terminal=True, color_system="standard")
    textual_adapter.set_color_system(console, "256")
    assert console.color_system == "256"
    assert textual_adapter.driver_of(App()) is None  # not running: no driver yet
    assert not textual_adapter.is_select_overlay(Input())
    palette = textual_adapter.rich_standard_palette()
    assert len(palette) == 16 and palette[0] == (0, 0, 0)


def private_uses(source: str) -> list[str]:
    """Imports of a private textual/rich module or name, and reads of the adapted
    attributes, in one module's source."""
    found = []
    for node in ast.walk(ast.parse(source)):
        if isinstance(node, ast.ImportFrom) and node.module:
            top = node.module.split(".")[0]
            if top in ("textual", "rich") and (
                    any(part.startswith("_") for part in node.module.split("."))
                    or any(a.name.startswith("_") for a in node.names)):
                found.append(f"from {node.module} import ...")
        elif isinstance(node, ast.Import):
            found += [f"import {a.name}" for a in node.names
                      if a.name.split(".")[0] in ("textual", "rich")
                      and any(p.startswith("_") for p in a.name.split("."))]
        elif isinstance(node, ast.Attribute) and node.attr in ADAPTED_ATTRIBUTES:
            found.append(f".{node.attr}")
    return found


def test_no_other_module_imports_or_touches_a_private_textual_or_rich_name():
    root = Path(cloth_tui.__file__).parent
    found = {str(p.relative_to(root)): uses for p in sorted(root.rglob("*.py"))
             if p != ADAPTER and (uses := private_uses(p.read_text(encoding="utf-8")))}
    assert found == {}


def test_the_scan_sees_each_kind_of_use():
    assert private_uses("from textual.widgets._select import SelectOverlay")
    assert private_uses("from rich._palettes import STANDARD_PALETTE")
    assert private_uses("from textual.keys import _character_to_key")
    assert private_uses("import rich._palettes")
    assert private_uses("d = self.app._driver")
    assert private_uses("self.console._color_system = x")
    assert not private_uses("from textual.widgets import Select\nself._driver_name = 1")
