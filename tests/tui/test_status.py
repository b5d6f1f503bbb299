"""The status line at several widths: both lines fit, and what every width keeps is there
(the state, both rates with the graphics mode, the particle count, the largest stretch, ΔE
with its unit, the material or solver and the tolerance's cost, the numerical damping, tears); and
notices never cover it."""

import dataclasses
import re

import pytest
from rich.text import Text

from cloth_tui.sim.run.run_stats import RunStats
from cloth_tui.tui.status import SPARK_AT_LEAST, RateMeter, Readout, cells

from .conftest import make_app, run, until

XPBD_STATS = RunStats(**{"energy": 0.446, "particles": 676, "frame_ms": 19.1, "step_ms": 1.736,
              "substeps_used": 11, "max_stretch": 0.0075, "mean_stretch": 0.0017,
              "solver": "xpbd", "error_tolerance": 0.01, "tolerance_met": True,
              "numerical_damping": 0.031, "torn": 3})
ALWAYS = ("sim 57 fps", "view 57 fps (blocks 256)", "676 particles", "0.75%",
          "-0.045 J", "xpbd · err", "1 % → 11 sub", "19.1 ms", "damping 3.1 %/s",
          "3 torn")


@pytest.fixture
def readout(monkeypatch):
    monkeypatch.setattr(RateMeter, "rate", lambda self, now=None: 57.0)
    r = Readout()
    r.graphics = "blocks 256"
    r.on_snapshot(0, dataclasses.replace(XPBD_STATS, energy=0.491))
    r.on_snapshot(1, XPBD_STATS)
    r.render_ms = 112.2
    return r


@pytest.mark.parametrize("width", [78, 90, 100, 110, 118, 130, 140, 158, 200])
@pytest.mark.parametrize("recording,paused", [(False, False), (True, True)])
def test_each_width_keeps_what_matters_and_fits(readout, width, recording, paused):
    state, cost = readout.text(paused=paused, recording=recording, iterations=4, substeps=4,
                               width=width)
    both = Text.from_markup(state).plain + " | " + Text.from_markup(cost).plain
    both = " ".join(both.split())  # the rates are padded to 3 digits where there is room
    for shown in ALWAYS:
        assert shown in both, (shown, both)
    assert re.search(r"ΔE (since restart )?-0\.045 J", both), both
    assert ("PAUSED" in both or "⏸" in both) == paused and ("●" in both) == recording
    assert cells(state) <= width
    room_for_spark = SPARK_AT_LEAST if "particles" in Text.from_markup(state).plain else 0
    assert cells(cost) <= width - room_for_spark


def test_a_wide_line_says_it_in_full_words(readout):
    state, cost = readout.text(paused=False, recording=False, iterations=4, substeps=4,
                               width=158)  # a 160-column terminal less the padding
    plain = Text.from_markup(state).plain
    assert "▶ running" in plain and "numerical damping 3.1 %/s" in plain
    assert "4 iterations × 4 (now 11) substeps" in Text.from_markup(cost).plain
    assert "xpbd · error 1 % → 11 substeps, 19.1 ms/frame" in Text.from_markup(cost).plain


def test_one_substep_is_said_in_the_singular(readout):
    readout.on_snapshot(2, dataclasses.replace(XPBD_STATS, substeps_used=1, material="denim"))
    _, cost = readout.text(paused=False, recording=False, iterations=2, substeps=1,
                           width=158)
    assert "denim · error 1 % → 1 substep, " in Text.from_markup(cost).plain


@pytest.mark.parametrize("width", [78, 110, 158])
def test_a_first_run_says_it_is_compiling_and_still_fits(readout, width):
    readout.compiling = "compiling kernels (first run only)… 12 compiled, 40 s"
    state, _ = readout.text(paused=False, recording=False, iterations=4, substeps=4,
                            width=width)
    plain = Text.from_markup(state).plain
    assert "compiling" in plain and cells(state) <= width
    assert "▶" not in plain and "sim 57" not in plain  # in place of "running" and the rate
    if width >= 158:
        assert "compiling kernels… 12 compiled, 40 s" in plain
    readout.compiling = ""
    state, _ = readout.text(paused=False, recording=False, iterations=4, substeps=4,
                            width=width)
    assert "compiling" not in Text.from_markup(state).plain


def test_the_app_line_fits_its_terminal_and_notices_stay_off_it(tmp_path):
    async def go():
        app = make_app(tmp_path)
        async with app.run_test(size=(160, 48), notifications=True) as pilot:
            await until(pilot, lambda: app.preview.frames_shown > 0, what="a frame")
            app.readout.on_snapshot(app.readout.last_frame + 1, XPBD_STATS)  # xpbd, as above
            for size in ((160, 48), (100, 30), (80, 24)):
                await pilot.resize_terminal(*size)
                await pilot.pause(0.2)
                app._refresh_status()
                await pilot.pause(0.1)
                text = app.query_one("#status-text")
                plain = text.render().plain + " " + app.query_one("#cost-text").render().plain
                assert text.render().cell_length <= text.size.width, size
                assert "damping 3.1 %/s" in plain and "676 particles" in plain, (size, plain)
            app.notify("a notice with a long text that would reach the right half " * 2)
            await until(pilot, lambda: app.screen.query("Toast"), what="the notice shown")
            await pilot.pause(0.2)
            bar = app.query_one("#status").region
            toasts = [t.region for t in app.screen.query("Toast")]
            assert toasts and not any(t.overlaps(bar) for t in toasts)
    run(go())


def test_a_runs_own_stats_name_its_material_and_what_its_accuracy_costs():
    """From a real run (no hand-made stats): a denim sheet tearing by strength says
    "denim · error … % → N substeps, … ms/frame", its error bound tightened for the
    tearing; the stretch shown beside it is the fabric's, not the error."""
    from cloth_tui.scene import Scene
    from cloth_tui.sim.run.runner import Simulation
    sim = Simulation(Scene().with_values({
        "cloth.resolution": 10, "behavior.solver": "xpbd", "behavior.tear": True,
        "material": {"preset": "denim", "tear_strength": 400.0}}))
    for _ in range(5):
        sim.advance_frame()
    stats = sim.stats()
    assert stats.material == "denim" and stats.error_tolerance < 0.05
    r = Readout()
    r.on_snapshot(sim.frames, stats)
    state, cost = r.text(paused=False, recording=False, iterations=4, substeps=4)
    expect = (f"denim · error {100 * stats.error_tolerance:g} % → {stats.substeps_used} "
              f"substeps, {stats.frame_ms:.1f} ms/frame")
    assert expect in Text.from_markup(cost).plain
    assert f"stretch max {100 * stats.max_stretch:.2f}%" in Text.from_markup(state).plain
