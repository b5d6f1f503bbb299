"""Kernel settings (sim/jit.py): a kernel compiled in this process and the same kernel loaded
from numba's cache give the same bits. A study's runs on Dask workers load the cache a
cold test process or first run has just written, and a chaotic run (lbfgs's clamped strip,
which never comes to rest at the lab's iterations) turns one ulp into a different result."""

import os
import subprocess
import sys

import pytest

RUN = """
import hashlib
from cloth_tui.lab import clamped
from cloth_tui.lab.study import lab_material
from cloth_tui.sim.run.runner import Simulation
m = lab_material("denim")
scene = clamped.clamped_strip(clamped.strip_for_load(8.0, m), 5, m, "lbfgs")[0]
sim = Simulation(scene)
for _ in range(120):
    sim.advance_frame()
print(hashlib.sha256(sim.state.x.tobytes()).hexdigest())
"""


@pytest.mark.heavy
def test_a_run_compiled_cold_equals_the_run_from_the_cache(tmp_path):
    env = {**os.environ, "NUMBA_CACHE_DIR": str(tmp_path / "numba")}

    def run() -> str:
        p = subprocess.run([sys.executable, "-c", RUN], env=env, capture_output=True,
                           text=True, timeout=600)
        assert p.returncode == 0, p.stderr
        return p.stdout.strip()

    cold = run()  # compiles every kernel of the step and writes the cache
    assert any((tmp_path / "numba").rglob("*.nbc"))
    assert run() == cold  # loads them
