"""Captures reach a browser visitor as downloads (`cloth-tui serve`), and only a browser one:
in a terminal, Textual's `deliver_binary` would copy each file into ~/Downloads.

Textual's own delivery (chunks over the web driver) is exercised end to end by
tests/test_serve.py in a real browser; here the app's side: which files it hands over."""

import pytest

from cloth_tui.scene import Scene
from cloth_tui.tui.app import ClothApp
from cloth_tui.tui.capture_actions import DOWNLOADING

from .conftest import SIZE, make_app, run, until


def _make(tmp_path, monkeypatch, web: bool, scene=None, **kwargs) -> ClothApp:
    """The app (fake renderer, paused) with Textual's `is_web` set, `deliver_binary`
    recording the path and name it is given (nothing sent) and every notice in `told`."""
    monkeypatch.setattr(ClothApp, "is_web", property(lambda self: web))
    told, notify = [], ClothApp.notify

    def keep_notices(self, message, **options):  # kept: a shown notice expires in 5 s
        told.append(message)
        return notify(self, message, **options)

    monkeypatch.setattr(ClothApp, "notify", keep_notices)
    app = make_app(tmp_path, scene, **kwargs)
    app.told = told
    app.delivered = []

    def deliver_binary(path, **options):
        with open(path, "rb"):  # Textual opens it at once: a missing file fails here
            pass
        app.delivered.append((path, options.get("name")))
        return "key"

    app.deliver_binary = deliver_binary
    return app


def test_a_saved_scene_is_downloaded_in_a_browser(tmp_path, monkeypatch):
    async def go():
        app = _make(tmp_path, monkeypatch, True)
        async with app.run_test(size=SIZE) as pilot:
            await pilot.press("s")
            await until(pilot, lambda: any("Scene saved" in m for m in app.told))
            (path,) = sorted(app.captures_dir.glob("scene-*.toml"))
            assert app.delivered == [(path, path.name)]
            assert any(m.endswith(DOWNLOADING) for m in app.told)
    run(go())


def test_a_capture_gone_before_its_download_is_reported(tmp_path, monkeypatch):
    async def go():
        app = _make(tmp_path, monkeypatch, True)
        async with app.run_test(size=SIZE) as pilot:
            await pilot.press("i")  # the fake renderer reports a file it never wrote
            await until(pilot, lambda: any("cannot download" in m for m in app.told))
            assert app.delivered == []
            assert any(m.startswith("Screenshot saved") and not m.endswith(DOWNLOADING)
                       for m in app.told)
    run(go())


def test_a_terminal_gets_no_downloads(tmp_path, monkeypatch):
    async def go():
        app = _make(tmp_path, monkeypatch, False)
        async with app.run_test(size=SIZE) as pilot:
            await pilot.press("s")
            await until(pilot, lambda: any("Scene saved" in m for m in app.told))
            assert app.delivered == []
            assert not any(DOWNLOADING in m for m in app.told)
    run(go())


def test_a_saved_bake_is_downloaded_in_a_browser(tmp_path, monkeypatch):
    pytest.importorskip("pxr")

    async def go():
        app = _make(tmp_path, monkeypatch, True, Scene().with_values({"cloth.resolution": 8}),
                    start_paused=False)
        async with app.run_test(size=SIZE) as pilot:
            await pilot.press("e")
            await until(pilot, lambda: app.bake.recording and app.bake.recorder.frames >= 3,
                        timeout=20, what="frames recorded")
            await pilot.press("e")
            await until(pilot, lambda: any(m.startswith("Bake saved") for m in
                                           app.told), timeout=20)
            (path,) = sorted(app.captures_dir.glob("bake-*.usdc"))
            assert app.delivered == [(path, path.name)]
    run(go())
