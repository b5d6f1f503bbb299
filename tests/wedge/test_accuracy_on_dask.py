"""The accuracy study on Dask gives the serial run's results (timings aside: measured where
each run ran)."""

import dataclasses
import json
import subprocess
import sys

import pytest

from cloth_tui.bench import accuracy as A

pytest.importorskip("distributed")

TIMINGS = ("time", "cpu_time", "elapsed", "wall_s")


def without_timings(v):
    if isinstance(v, dict):
        return {k: without_timings(x) for k, x in v.items() if k not in TIMINGS}
    if isinstance(v, list):
        return [without_timings(x) for x in v]
    return v


@pytest.mark.heavy
def test_a_small_study_on_two_workers_equals_the_serial_one():
    from cloth_tui.bench.accuracy_cli import _run_on_dask
    cfg = dataclasses.replace(
        A.StudyConfig.quick(), timing_budget=0.0, t_end=0.2,
        ladders={"rk4": (1 / 125, 1 / 250), "explicit_euler": (1 / 60, 1 / 2000)},
        pbd_dts=(1 / 60,), pbd_iterations=(4,), stability_stiffness=(200.0,),
        stability_bisections=2, stability_t_end=0.1, sag_iterations=(1, 4), sag_t_end=0.5,
        cantilever_links=(5,))  # one resolution: each solver's strip runs up to 40 periods
    serial = A.run_study(cfg)
    on_dask = _run_on_dask(cfg, None, 2, None)
    a, b = without_timings(serial), without_timings(on_dask)
    assert json.dumps(a, default=str) == json.dumps(b, default=str)
    assert [p["stable"] for p in b["points"]].count(False) >= 1  # an unstable point as well
    assert set(b["stability"]["methods"]) == set(A.INTEGRATORS)


@pytest.mark.slow
def test_accuracy_quick_with_workers_equals_the_serial_run():
    def study(*extra):
        p = subprocess.run([sys.executable, "-m", "cloth_tui", "accuracy", "--quick", "--json",
                            *extra], capture_output=True, text=True, timeout=1200)
        assert p.returncode == 0, p.stderr
        return without_timings(json.loads(p.stdout))
    assert study() == study("--workers", "2")
