"""The private parts of Textual and Rich the app needs, each reached here and nowhere else,
so an upgrade that moves one breaks this module (and its test) rather than the app at a
random moment. Each has no public equivalent in the versions this project runs on:

- `SelectOverlay` (textual.widgets._select): the open Select's list, which takes typed keys
  as an Input does;
- `App._driver`: the driver's write queue, the one place bytes reach the terminal in order
  with Textual's own screen updates;
- `Screen._compositor.visible_widgets`: what is painted over a widget, topmost first;
- `Console._color_system`: the colour depth, set to what the terminal was found to have;
- `rich._palettes.STANDARD_PALETTE`: the colours Rich takes the 16 system colours to be;
- the classes Textual itself sets on a folded Collapsible (`-collapsed`) and on an Input with
  no validators (`-valid`) when they mount. Given at construction, setting them changes
  nothing; set at mount, each restyles the widget and everything in it (the panels' ~700
  widgets). Renamed, they would only cost that time again (tests/tui/test_start_styles.py
  sees it).

Textual is imported only when a function needs it: tui/graphics (no Textual) reads the
palette through here too.
"""

from __future__ import annotations

from typing import Any, Iterator, Mapping

COLLAPSED_CLASS = "-collapsed"  # textual.widgets.Collapsible._update_collapsed
VALID_INPUT_CLASS = "-valid"    # textual.widgets.Input.validate, with no validators


def is_select_overlay(widget: Any) -> bool:
    """Whether `widget` is an open Select's list of options."""
    from textual.widgets._select import SelectOverlay
    return isinstance(widget, SelectOverlay)


def driver_of(app: Any) -> Any | None:
    """The app's driver (None before it runs or after it stops)."""
    return app._driver


def widgets_painted_over(screen: Any) -> Iterator[tuple[Any, Any, Any]]:
    """(widget, region, clip) of the screen's visible widgets, topmost first."""
    visible: Mapping = screen._compositor.visible_widgets
    for widget, (region, clip) in visible.items():
        yield widget, region, clip


def set_color_system(console: Any, name: str) -> None:
    """Make the console render at colour depth `name` (a key of rich.console.COLOR_SYSTEMS:
    'standard', '256', 'truecolor'), whatever the environment announced."""
    from rich.console import COLOR_SYSTEMS
    console._color_system = COLOR_SYSTEMS[name]


def rich_standard_palette() -> list[tuple[int, int, int]]:
    """Rich's RGB for the 16 system colours, in their order."""
    from rich._palettes import STANDARD_PALETTE
    return [tuple(STANDARD_PALETTE[i]) for i in range(16)]


def missing_private_names() -> list[str]:
    """The private names above that the installed Textual and Rich no longer have (each
    looked for where the app finds it: on a fresh App, Screen and Console)."""
    checks = {
        "textual.widgets._select.SelectOverlay": _select_overlay_class,
        "App()._driver": lambda: _fresh("textual.app", "App")._driver,
        "Screen()._compositor.visible_widgets":
            lambda: type(_fresh("textual.screen", "Screen")._compositor).visible_widgets,
        "Console()._color_system": lambda: _fresh("rich.console", "Console")._color_system,
        "rich._palettes.STANDARD_PALETTE[0..15]": rich_standard_palette,
    }
    missing = []
    for name, check in checks.items():
        try:
            check()
        except (ImportError, AttributeError, IndexError, TypeError):
            missing.append(name)
    return missing


def _select_overlay_class() -> type:
    from textual.widgets._select import SelectOverlay
    return SelectOverlay


def _fresh(module: str, name: str) -> Any:
    import importlib
    return getattr(importlib.import_module(module), name)()
