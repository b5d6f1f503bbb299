"""SVG snapshots of the main screen and of each control group, with the simulation frozen
(paused from the start, so every frame shows the initial sheet) and the rates fixed at 0.

Baselines live in tests/tui/__snapshots__/. After an intended change of the look,
regenerate them with

    CLOTH_TUI_UPDATE_SNAPSHOTS=1 pytest tests/tui/test_snapshots.py

and review the new SVGs (open them in a browser) before committing. A mismatch writes the
actual screen next to the baseline as NAME.actual.svg.
"""

import os
from pathlib import Path

import pytest
from textual.containers import ScrollableContainer
from textual.widgets import Collapsible

from cloth_tui.scene import Scene
from cloth_tui.scene_files import load
from cloth_tui.tui.status import RateMeter

from .conftest import SIZE, make_app, run, until

SNAPSHOTS = Path(__file__).parent / "__snapshots__"
UPDATE = os.environ.get("CLOTH_TUI_UPDATE_SNAPSHOTS") == "1"


def check(name: str, svg: str) -> str | None:
    path = SNAPSHOTS / f"{name}.svg"
    actual = SNAPSHOTS / f"{name}.actual.svg"
    if UPDATE or not path.exists():
        SNAPSHOTS.mkdir(exist_ok=True)
        path.write_text(svg, encoding="utf-8")
        actual.unlink(missing_ok=True)
        return None if UPDATE else f"{name}: no baseline; wrote {path}, check and commit it"
    if path.read_text(encoding="utf-8") != svg:
        actual.write_text(svg, encoding="utf-8")
        return f"{name}: differs from {path}; see {actual}"
    actual.unlink(missing_ok=True)
    return None


def shots(app, pilot, problems):
    async def shot(name):
        app._refresh_status()
        await pilot.pause(0.1)
        problems.append(check(name, app.export_screenshot(title="cloth-tui")))
    return shot


def test_screens_match_baselines(tmp_path, monkeypatch):
    monkeypatch.setattr(RateMeter, "rate", lambda self, now=None: 0.0)
    problems = []

    async def go():
        app = make_app(tmp_path)
        async with app.run_test(size=SIZE) as pilot:
            await until(pilot, lambda: app.preview.frames_shown > 1 and app._crosshair_placed)
            await pilot.pause(0.5)  # status refresh (5 Hz) and layout settle
            shot = shots(app, pilot, problems)

            await shot("main")
            groups = {c.id: c for c in app.query(Collapsible)}
            for name in ("scene", "behavior", "appearance"):
                for c in groups.values():
                    c.collapsed = c.id != f"group-{name}"
                await pilot.pause(0.1)
                await shot(f"panel-{name}")
            await pilot.press("c")
            await shot("controls-hidden")

    run(go())
    problems = [p for p in problems if p]
    if problems:
        pytest.fail("\n".join(problems))


def test_pin_groups_listed_match_baseline(tmp_path, monkeypatch):
    """The Scene group scrolled to its pin groups (the curtain's six hooks), one opened."""
    monkeypatch.setattr(RateMeter, "rate", lambda self, now=None: 0.0)
    problems = []

    async def go():
        app = make_app(tmp_path, load("curtain"))
        async with app.run_test(size=SIZE) as pilot:
            await until(pilot, lambda: app.preview.frames_shown > 1 and app._crosshair_placed)
            for c in app.query(Collapsible):
                c.collapsed = c.id not in ("group-scene", "pins-1")
            pins = app.query_one("#pins-1")
            drawer = next(a for a in pins.ancestors if isinstance(a, ScrollableContainer))
            # scroll once the collapsed groups' layout has settled, and again until the
            # offset stays; the scrollbar is not in the shot: its thumb's eighths of a cell
            # differed from run to run with the same lines shown
            drawer.styles.scrollbar_visibility = "hidden"
            offsets: list = []
            while len(offsets) < 3 or len(set(offsets[-2:])) > 1:
                await pilot.pause(0.1)
                pins.scroll_visible(animate=False, top=True)
                await pilot.pause(0.1)
                offsets.append((drawer.virtual_size, drawer.scroll_y))
                assert len(offsets) < 50, "the drawer's scroll offset never settled"
            await shots(app, pilot, problems)("panel-pins")

    run(go())
    problems = [p for p in problems if p]
    if problems:
        pytest.fail("\n".join(problems))


def test_80x24_screens_match_baselines(tmp_path, monkeypatch):
    """A narrow terminal: the preview takes the width, the drawer opens over it, the help."""
    monkeypatch.setattr(RateMeter, "rate", lambda self, now=None: 0.0)
    problems = []

    async def go():
        app = make_app(tmp_path)
        async with app.run_test(size=(80, 24)) as pilot:
            await until(pilot, lambda: app.preview.frames_shown > 1 and app._crosshair_placed)
            await pilot.pause(0.5)
            shot = shots(app, pilot, problems)
            await shot("narrow-main")
            await pilot.press("c")
            await shot("narrow-drawer")
            await pilot.press("c", "question_mark")
            await shot("narrow-help")

    run(go())
    problems = [p for p in problems if p]
    if problems:
        pytest.fail("\n".join(problems))


def test_fabric_screens_match_baselines(tmp_path, monkeypatch):
    """Denim on: the Fabric group (its list and values in units), and the Scene and
    Behavior groups with the keys it replaces shown as such."""
    monkeypatch.setattr(RateMeter, "rate", lambda self, now=None: 0.0)
    problems = []

    async def go():
        app = make_app(tmp_path, Scene().with_value("material.preset", "denim"))
        async with app.run_test(size=SIZE) as pilot:
            await until(pilot, lambda: app.preview.frames_shown > 1 and app._crosshair_placed
                        and app.readout.stats.material == "denim")
            await pilot.pause(0.5)
            shot = shots(app, pilot, problems)
            groups = list(app.query(Collapsible))
            for name in ("fabric", "scene", "behavior"):
                for c in groups:
                    c.collapsed = c.id != f"group-{name}"
                await pilot.pause(0.1)
                await shot(f"fabric-{name}")

    run(go())
    problems = [p for p in problems if p]
    if problems:
        pytest.fail("\n".join(problems))
