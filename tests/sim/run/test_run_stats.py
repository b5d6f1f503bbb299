"""RunStats: a typed record of a run, refreshed frame by frame, and the only way statistics
are read (no reader guesses a default for a key)."""

import json
import re
from pathlib import Path

import cloth_tui
from cloth_tui.scene import Scene
from cloth_tui.sim.run.run_stats import FrameStats, RunStats
from cloth_tui.sim.run.runner import Simulation


def test_a_refresh_keeps_the_costly_numbers_and_takes_the_frames():
    full = RunStats(measured=True, particles=9, max_stretch=0.25, energy=1.5, frames=3,
                    torn=1, tolerance_met=True)
    later = full.refreshed(FrameStats(frames=4, torn=2, tolerance_met=False, frame_ms=7.0))
    assert (later.particles, later.max_stretch, later.energy) == (9, 0.25, 1.5)
    assert (later.frames, later.torn, later.tolerance_met, later.frame_ms) == (4, 2, False, 7.0)
    assert full.frames == 3  # frozen: the earlier set is not changed


def test_nothing_measured_reads_as_such():
    s = RunStats()
    assert not s.measured and s.energy is None and s.error is None and s.particles == 0


def test_a_run_reports_a_run_stats_and_its_snapshots_carry_one():
    sim = Simulation(Scene().with_value("cloth.resolution", 8))
    sim.advance_frame()
    st = sim.stats()
    assert isinstance(st, RunStats) and st.measured and st.frames == 1
    assert st.particles == 64 and st.effects and st.energy is not None
    sim.advance_frame()
    snap = sim.snapshot(st)
    assert snap.stats.frames == 2 and snap.stats.energy == st.energy  # carried, not measured
    bare = sim.snapshot(RunStats())
    assert bare.stats.frames == 2 and not bare.stats.measured
    json.dumps(st.as_dict())  # what `simulate --json` prints


# A dict read with a guessed default: `stats.get("energy", 0.0)`, `stats["torn"]`.
DICT_READ = re.compile(r"stats\w*(\(\))?\s*(\.get\(|\[\s*['\"])")


def test_no_module_reads_run_statistics_as_a_dict():
    root = Path(cloth_tui.__file__).parent
    found = [f"{p.relative_to(root)}:{n}: {line.strip()}"
             for p in sorted(root.rglob("*.py"))
             for n, line in enumerate(p.read_text().splitlines(), 1) if DICT_READ.search(line)]
    assert found == []


def test_the_dict_read_check_sees_one():
    assert DICT_READ.search('e = snap.stats.get("energy", 0.0)')
    assert DICT_READ.search("n = sim.stats()['torn']")
    assert not DICT_READ.search("n = sim.stats().torn")


def test_a_measured_number_that_is_not_finite_makes_the_run_not_finite_and_json_null():
    bad = RunStats(measured=True, min_y=0.0, max_speed=1.0, max_stretch=0.1,
                   mean_stretch=0.05, energy=float("nan"), error=float("inf"))
    assert bad.finite is False
    d = json.loads(json.dumps(bad.as_dict(), allow_nan=False))
    assert d["energy"] is None and d["error"] is None and d["finite"] is False
    assert bad.refreshed(FrameStats(frames=2)).finite is False


def test_finite_numbers_keep_finite_and_nothing_measured_is_not_a_failure():
    good = RunStats(measured=True, min_y=0.0, max_speed=1.0, max_stretch=0.1,
                    mean_stretch=0.05, energy=1.0, error=None)
    assert good.finite and good.as_dict()["max_stretch"] == 0.1
    assert RunStats().finite  # its NaNs read "not measured"
    json.dumps(RunStats().as_dict(), allow_nan=False)
