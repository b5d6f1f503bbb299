import asyncio
import time

import pytest

from cloth_tui.scene import Scene
from cloth_tui.tui.app import ClothApp

from .fakes import FakeRenderService

SIZE = (160, 48)


async def until(pilot, condition, timeout: float = 30.0, what: str = "condition") -> None:
    """Let the app run until `condition()` holds (it polls other threads' results). The
    timeout only bounds a failing test: a wait that succeeds returns at once, and on a
    loaded machine 20 frames of a fresh app took over 5 s."""
    deadline = time.monotonic() + timeout
    while not condition():
        if time.monotonic() > deadline:
            raise AssertionError(f"timed out waiting for {what}")
        await pilot.pause(0.02)


def make_app(tmp_path, scene: Scene | None = None, **kwargs) -> ClothApp:
    kwargs.setdefault("renderer_factory", FakeRenderService)
    kwargs.setdefault("start_paused", True)  # commands still run; less CPU for the tests
    return ClothApp(scene or Scene(), tmp_path / "caps", **kwargs)


def sim_scene(app: ClothApp) -> Scene:
    return app.sim.sim.scene


def notifications(app: ClothApp) -> list[str]:
    return [n.message for n in app._notifications]


@pytest.fixture
def anyio_backend():
    return "asyncio"


def run(coro):
    return asyncio.run(coro)


@pytest.fixture(autouse=True)
def quick_idle(monkeypatch):
    """Textual's Pilot waits for the *process* to go idle (CPU time vs wall time), up to 1 s
    per step. The simulation thread keeps a core busy by design, so every step would take the
    full second; conditions are awaited explicitly with `until` instead."""
    import importlib

    from textual import _wait

    original = _wait.wait_for_idle

    async def quick(min_sleep: float = 0.0, max_sleep: float = 1.0) -> None:
        await original(0.0, min(max_sleep, 0.05))

    for name in ("textual.pilot", "textual.app"):
        monkeypatch.setattr(importlib.import_module(name), "wait_for_idle", quick)
