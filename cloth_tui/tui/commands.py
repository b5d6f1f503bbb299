"""Command palette entries: open a built-in scene, pick a fabric, and the app's main
actions."""

from __future__ import annotations

from functools import partial

from typing import Callable, Iterable

from textual.app import SystemCommand
from textual.command import DiscoveryHit, Hit, Hits, Provider

from ..materials.catalogue import preset_rows
from ..materials.section import ORIGINAL
from ..resources import builtin_scenes


def _first_comment(path) -> str:
    try:
        line = path.read_text(encoding="utf-8").splitlines()[0]
    except (OSError, IndexError, UnicodeDecodeError):
        return ""
    return line.lstrip("# ").strip() if line.startswith("#") else ""


class SceneCommands(Provider):
    """`Open scene: NAME` for every built-in scene."""

    def _entries(self):
        for name, path in builtin_scenes().items():
            yield f"Open scene: {name}", partial(self.app.open_scene, name), _first_comment(path)

    async def discover(self) -> Hits:
        for text, callback, help in self._entries():
            yield DiscoveryHit(text, callback, help=help)

    async def search(self, query: str) -> Hits:
        matcher = self.matcher(query)
        for text, callback, help in self._entries():
            score = matcher.match(text)
            if score > 0:
                yield Hit(score, matcher.highlight(text), callback, help=help)


class FabricCommands(Provider):
    """`Fabric: NAME` for "original" and every preset, with what it is, its weight and its
    source."""

    def _entries(self):
        yield (f"Fabric: {ORIGINAL}", partial(self.app.choose_fabric, ORIGINAL),
               "the unitless sheet: no fabric")
        for row in preset_rows():
            yield (f"Fabric: {row.name}", partial(self.app.choose_fabric, row.name),
                   f"{row.kind} · {row.grams_per_m2:.0f} g/m² · {row.source}")

    async def discover(self) -> Hits:
        for text, callback, help in self._entries():
            yield DiscoveryHit(text, callback, help=help)

    async def search(self, query: str) -> Hits:
        matcher = self.matcher(query)
        for text, callback, help in self._entries():
            score = matcher.match(text)
            if score > 0:
                yield Hit(score, matcher.highlight(text), callback, help=help)


def with_own_screenshot(commands: Iterable[SystemCommand],
                        screenshot: Callable[[], object]) -> Iterable[SystemCommand]:
    """Textual's system commands, its "Screenshot" (an SVG of the terminal screen) replaced
    by the app's own, the `i` key's: a PNG of the view in the captures folder."""
    for command in commands:
        if command.title == "Screenshot":
            yield SystemCommand("Screenshot", "save a PNG of the view to the captures folder "
                                "(the i key)", screenshot)
        else:
            yield command
