"""The Dask engine on a real LocalCluster: a worker killed mid-way is replaced and its task
run again, and every result still comes back."""

import os
import signal

import pytest

pytest.importorskip("distributed")

from cloth_tui.scene_files import load  # noqa: E402
from cloth_tui.wedge.engine import Engine, Failed  # noqa: E402
from cloth_tui.wedge.plan import plan  # noqa: E402
from cloth_tui.wedge.task import run_cell  # noqa: E402


def test_a_worker_killed_mid_way_is_replaced_and_every_run_comes_back():
    base = load("default").with_values({"cloth.resolution": 8})
    _, cells = plan(base, ["forces.wind=true", "forces.wind_strength=1,3,5,7,9,11"])
    killed = []

    with Engine(workers=2) as engine:
        def kill_a_busy_worker(i, result):
            if killed:
                return
            busy = [w for w, keys in engine.client.processing().items() if keys]
            pids = engine.client.run(os.getpid, workers=busy[:1])
            (pid,) = pids.values()
            os.kill(pid, signal.SIGKILL)
            killed.append(pid)

        results = engine.run(run_cell, [(c.scene, 40, (32, 24), False) for c in cells],
                             kill_a_busy_worker)
        engine.client.wait_for_workers(2, timeout=120)  # the nanny starts a new process
        workers_after = set(engine.client.run(os.getpid).values())

    assert killed and killed[0] not in workers_after  # it died, and a new one took its place
    assert len(workers_after) == 2
    assert not any(isinstance(r, Failed) or r is None for r in results)
    assert [r["image"].shape for r in results] == [(24, 32, 3)] * len(cells)
    # the runs differ as their wind does: each result belongs to its own cell
    drift = [r["energy_drift"] for r in results]
    assert len(set(drift)) == len(drift)


def test_stop_cancels_what_is_left_and_keeps_what_is_done():
    base = load("default").with_values({"cloth.resolution": 8})
    _, cells = plan(base, ["scene.friction=0,0.2,0.4,0.6,0.8,1"])
    done = []
    with Engine(workers=1) as engine:
        results = engine.run(run_cell, [(c.scene, 30, (32, 24), False) for c in cells],
                             lambda i, r: done.append(i), stop=lambda: len(done) >= 1)
    finished = [r for r in results if r is not None]
    assert 1 <= len(finished) < len(cells)
    assert all(isinstance(r, dict) for r in finished)
