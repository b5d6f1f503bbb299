"""Soak: thousands of random key presses and setting changes, valid and not, against the
running app (simulation thread live). Asserts no exception anywhere (the app, every
simulation thread it started) and bounded memory growth. A short form runs in CI; the long
form is marked slow."""

from __future__ import annotations

import gc
import os
import random

import pytest

from cloth_tui.scene import Scene, all_keys, key_spec
from cloth_tui.sim.run.runner import Simulation
from cloth_tui.tui import app as app_module

from .conftest import SIZE, make_app, run, until

KEYS = ["space", "r", "w", "a", "i", "v", "s", "c", "up", "down", "left", "right", "pageup",
        "pagedown", "h", "j", "k", "l", "left_square_bracket", "right_square_bracket",
        "comma", "full_stop", "plus", "minus", "o", "0", "question_mark", "escape", "tab"]

# Keys whose change makes each frame much dearer; kept small so the soak stays a soak of the
# app, not a benchmark of a 512² sheet.
CAPPED = {"cloth.resolution": (2, 24), "behavior.iterations": (1, 8),
          "behavior.substeps": (1, 4), "behavior.frame_rate": (10.0, 120.0)}
SKIPPED = {"behavior.self_collision", "behavior.solver", "appearance.cloth_texture",
           "appearance.ground_texture"}


def random_value(rng: random.Random, dotted: str):
    """A plausible value, or (a third of the time) something the scene must refuse."""
    m = key_spec(dotted).metadata
    if rng.random() < 0.33:
        return rng.choice([float("nan"), -1e9, "garbage", [0, 0, 0], None, True, 1e300])
    if dotted in CAPPED:
        lo, hi = CAPPED[dotted]
        return rng.randint(lo, hi) if isinstance(lo, int) else rng.uniform(lo, hi)
    if m["choices"]:
        return rng.choice(m["choices"])
    if m["kind"] == "color":
        return "#%06x" % rng.randrange(1 << 24)
    if m["kind"].startswith("vec3"):
        return [rng.uniform(-1, 1) for _ in range(3)]
    default = Scene().get(dotted)
    if isinstance(default, bool):
        return rng.random() < 0.5
    if isinstance(default, int):
        return max(0, int(default * rng.uniform(0, 2)))
    if isinstance(default, float):
        lo = m["lo"] if m["lo"] is not None else -10.0
        hi = min(m["hi"] if m["hi"] is not None else 10.0, 10 * max(abs(default), 1.0))
        return rng.uniform(lo, hi)
    return default


def rss_bytes() -> int:
    """Resident memory of this process (tracemalloc would slow the soak several-fold)."""
    with open("/proc/self/statm") as fh:
        return int(fh.read().split()[1]) * os.sysconf("SC_PAGE_SIZE")


class SimulationThreads:
    """Every simulation thread the app starts. `r` replaces a dead thread with a new one, so
    looking only at `app.sim` after a random `r` would hide that the previous one died."""

    def __init__(self, monkeypatch):
        self.started: list[app_module.SimulationThread] = []
        watch = self

        class Watched(app_module.SimulationThread):
            def __init__(self, *args, **kwargs):
                super().__init__(*args, **kwargs)
                watch.started.append(self)

        monkeypatch.setattr(app_module, "SimulationThread", Watched)

    def errors(self) -> list[BaseException]:
        return [t.error for t in self.started if t.error is not None]


def soak(tmp_path, monkeypatch, actions: int, seed: int = 7) -> None:
    rng = random.Random(seed)
    keys = [k for k in all_keys() if k not in SKIPPED]
    threads = SimulationThreads(monkeypatch)

    async def go():
        app = make_app(tmp_path, start_paused=False)
        async with app.run_test(size=SIZE) as pilot:
            await pilot.pause(0.2)
            base = None
            for n in range(actions):
                if rng.random() < 0.7:
                    await pilot.press(rng.choice(KEYS))
                else:
                    dotted = rng.choice(keys)
                    app.set_value(dotted, random_value(rng, dotted))
                if n % 50 == 0:
                    await pilot.pause(0.01)
                assert not threads.errors(), f"a simulation thread died: {threads.errors()}"
                if n == actions // 4:
                    gc.collect()
                    base = rss_bytes()
            gc.collect()
            grown = rss_bytes() - (base or 0)
            assert threads.started and not threads.errors(), threads.errors()
            # After the first quarter (caches, compiled kernels and sheets of every size
            # seen), memory may grow only by bounded logs and caches: 100 MB is a leak.
            assert grown < 100e6, f"memory grew by {grown / 1e6:.1f} MB"
            await pilot.press("q")

    run(go())


@pytest.mark.heavy
def test_soak_short(tmp_path, monkeypatch):
    soak(tmp_path, monkeypatch, actions=120)


@pytest.mark.slow
def test_soak_long(tmp_path, monkeypatch):
    soak(tmp_path, monkeypatch, actions=4000, seed=11)


def test_a_simulation_thread_that_died_is_seen_after_r_replaced_it(tmp_path, monkeypatch):
    """What the soak relies on: the thread dies once in its frame path, `r` starts a new one
    (so `app.sim.error` is clean again), and the watch still reports the death."""
    threads = SimulationThreads(monkeypatch)
    advance = Simulation.advance_frame
    failed: list[RuntimeError] = []

    def fails_once(sim):
        if not failed:
            failed.append(RuntimeError("injected failure in the frame path"))
            raise failed[0]
        advance(sim)

    monkeypatch.setattr(Simulation, "advance_frame", fails_once)

    async def go():
        app = make_app(tmp_path, start_paused=False)
        async with app.run_test(size=SIZE) as pilot:
            await until(pilot, lambda: threads.errors(), what="the simulation thread to die")
            await pilot.press("r")
            await until(pilot, lambda: app.sim is not threads.started[0] and
                        app.sim.latest.frame > 0, what="a new simulation thread running")
            assert app.sim.error is None  # what the soak used to look at
            assert threads.errors() == failed
            await pilot.press("q")

    run(go())
