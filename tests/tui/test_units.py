"""The plain parts of the TUI, without an app: image → half-block strips, rates, readout."""

import numpy as np

from cloth_tui.tui.panels import format_value, parse_text
from cloth_tui.tui.preview import CROSSHAIR, HALF, StyleCache, image_to_strips, resample
from cloth_tui.sim.run.run_stats import RunStats
from cloth_tui.tui.status import RateMeter, Readout


def test_resample_averages_exact_multiples_and_picks_otherwise():
    img = np.zeros((8, 4, 3), np.uint8)
    img[0, 0] = 200  # one of the 2×2 pixels of cell (0, 0)'s top half
    out = resample(img, 2, 2)
    assert out.shape == (4, 2, 3) and out[0, 0, 0] == 50
    odd = resample(np.zeros((7, 5, 3), np.uint8), 3, 2)
    assert odd.shape == (4, 3, 3)


def test_strips_are_half_blocks_with_top_and_bottom_colours():
    img = np.zeros((4, 3, 3), np.uint8)
    img[0] = (255, 0, 0)
    img[1] = (0, 0, 255)
    strips = image_to_strips(img, 3, 2, StyleCache(), crosshair=(1, 1))
    assert len(strips) == 2 and all(s.cell_length == 3 for s in strips)
    seg = list(strips[0])[0]
    assert seg.text == HALF * 3  # one run of equal cells → one segment
    assert seg.style.color.triplet == (252, 0, 0) and seg.style.bgcolor.triplet == (0, 0, 252)
    assert "".join(s.text for s in strips[1]) == HALF + CROSSHAIR + HALF


def test_rate_meter_and_readout():
    m = RateMeter(window=1.0)
    for i in range(11):
        m.add(i * 3, now=i * 0.1)
    assert abs(m.rate(now=1.0) - 30.0) < 1e-9
    assert m.rate(now=5.0) == 0.0  # nothing new for longer than the window
    r = Readout()
    r.on_snapshot(0, RunStats(**{"energy": 1.0, "particles": 4, "frame_ms": 2.0, "step_ms": 1.0}))
    r.on_snapshot(1, RunStats(**{"energy": 0.75, "particles": 4, "frame_ms": 6.0, "step_ms": 3.0,
                      "substeps_used": 2}))
    assert r.drift == -0.25 and r.step_ms == 3.0 and r.frame_ms == 6.0
    state, cost = r.text(paused=False, recording=True, iterations=4, substeps=2)
    assert "REC" in state and "4 particles" in state and "4 iterations × 2 substeps" in cost
    assert "6.00" in cost and "ms/frame" in cost
    r.on_snapshot(2, RunStats(**{"energy": 0.7, "substeps_used": 8, "halted": "diverges"}))
    state, cost = r.text(paused=False, recording=False, iterations=4, substeps=2)
    assert "HALTED" in state and "2 (now 8) substeps" in cost
    r.on_snapshot(0, RunStats(**{"energy": 2.0}))  # frame went back: a restart
    assert r.drift == 0.0


def test_readout_names_the_material_and_shows_what_the_tolerance_costs():
    r = Readout()
    r.on_snapshot(1, RunStats(**{"material": "denim", "solver": "xpbd", "error_tolerance": 0.005,
                      "substeps_used": 9, "frame_ms": 4.1, "tolerance_met": True,
                      "numerical_damping": 2e-4}))
    state, cost = r.text(paused=False, recording=False, iterations=4, substeps=4)
    assert "denim · error 0.5 % → 9 substeps, 4.1 ms/frame" in cost
    assert "NOT MET" not in cost and "damping" not in state  # too little to show
    r.on_snapshot(2, RunStats(**{"solver": "pbd", "error_tolerance": 0.05, "energy_tolerance": 0.05,
                      "substeps_used": 128, "frame_ms": 40.0, "tolerance_met": False,
                      "numerical_damping": 0.123}))
    state, cost = r.text(paused=False, recording=False, iterations=4, substeps=4)
    assert ("[b black on yellow] pbd · error 5 %, damping 5 %/s → 128 substeps, 40.0 "
            "ms/frame: NOT MET [/]") in cost
    assert "numerical damping 12.3 %/s" in state


def test_compact_readout_fits_80_columns_with_fps_stretch_and_energy(monkeypatch):
    from rich.text import Text
    monkeypatch.setattr(RateMeter, "rate", lambda self, now=None: 999.0)  # 3 digits
    r = Readout()
    for frame, e in ((0, 123.456), (1, -99.999)):
        r.on_snapshot(frame, RunStats(**{"energy": e, "max_stretch": 0.1234, "frame_ms": 123.4,
                              "step_ms": 12.345, "substeps_used": 128}))
    r.render_ms = 999.9
    for recording, paused in ((False, False), (False, True), (True, True)):
        state, cost = r.text(paused=paused, recording=recording, iterations=64, substeps=128,
                             width=78)
        plain = Text.from_markup(state).plain
        assert "sim 999 fps" in plain and "view 999 fps" in plain and "12.34%" in plain
        assert "ΔE -223.5 J" in plain
        assert len(plain) <= 78 and len(Text.from_markup(cost).plain) <= 78
        assert ("REC" in plain) == recording


def test_input_text_parsing():
    assert parse_text("forces.wind_direction", "[1, 0, -2]") == [1.0, 0.0, -2.0]
    assert parse_text("forces.wind_direction", "1 0 x") == "1 0 x"  # refused later
    assert parse_text("cloth.resolution", "12") == 12
    assert parse_text("cloth.resolution", "1.5") == 1.5  # refused later: not an integer
    assert parse_text("cloth.size", "abc") == "abc"
    assert parse_text("cloth.size", "1.5") == 1.5  # one number: a square
    assert parse_text("cloth.size", "2, 0.5") == [2.0, 0.5]  # two: [width, length]
    assert parse_text("cloth.size", "[2 0.5]") == [2.0, 0.5]
    assert parse_text("cloth.size", "2, wide") == "2, wide"  # refused later
    assert parse_text("cloth.resolution", "31, 11") == [31, 11]
    assert parse_text("cloth.resolution", "31, 1.5") == [31, 1.5]  # refused later
    assert parse_text("cloth.resolution", "") == ""
    assert format_value([2.0, 0.5]) == "2, 0.5" and format_value([31, 11]) == "31, 11"
    assert format_value([1.0, 0.0, 0.5]) == "1, 0, 0.5" and format_value(1e-8) == "1e-08"


def test_unchanged_rows_keep_their_strips_and_the_picture_is_the_same():
    from cloth_tui.tui.preview import RowCache

    rng = np.random.default_rng(3)
    a = rng.integers(0, 256, size=(16, 8, 3), dtype=np.uint8)
    b = a.copy()
    b[4:6] = 255 - b[4:6]  # changes terminal row 2 (pixel rows 4 and 5) only
    styles, cache = StyleCache(), RowCache()
    first = image_to_strips(a, 8, 8, styles, cache=cache)
    second = image_to_strips(b, 8, 8, styles, crosshair=(1, 5), cache=cache)
    fresh = image_to_strips(b, 8, 8, StyleCache(), crosshair=(1, 5))
    assert [s.text for s in second] == [s.text for s in fresh]
    assert [[seg.style for seg in s] for s in second] == [[seg.style for seg in s]
                                                         for s in fresh]
    kept = [r for r in range(8) if second[r] is first[r]]
    assert kept == [0, 1, 3, 4, 6, 7]  # row 2 changed; row 5 carries the crosshair
    third = image_to_strips(b, 8, 8, styles, cache=cache)
    assert third[5] is first[5] and CROSSHAIR not in third[5].text  # kept without the mark
