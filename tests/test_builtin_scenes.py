"""Every built-in scene: a one-line description, loads, and runs 300 frames stably."""

import subprocess
import sys

import numpy as np
import pytest

from cloth_tui.resources import builtin_scenes
from cloth_tui.scene_files import load
from cloth_tui.sim.run.runner import Simulation

REQUIRED = ("default", "sphere", "box", "moving-sphere", "flag-in-wind", "rain", "black-hole",
            "self-collision-fold", "tilted-plane", "multi-object")


def test_the_required_scenes_exist():
    assert set(REQUIRED) <= set(builtin_scenes())


@pytest.mark.parametrize("name", sorted(builtin_scenes()))
def test_scene_starts_with_a_one_line_description(name):
    first = builtin_scenes()[name].read_text(encoding="utf-8").splitlines()[0]
    assert first.startswith("# ") and len(first) > 10


@pytest.mark.parametrize("name", sorted(builtin_scenes()))
def test_scene_runs_300_frames_stably(name):
    scene = load(name)
    sim = Simulation(scene)
    for _ in range(300):
        sim.advance_frame()
    st = sim.stats()
    assert st.finite and np.isfinite(st.energy)
    assert st.recoveries == 0
    assert st.penetration <= scene.scene.thickness + 1e-3
    assert st.max_stretch < 0.5
    assert st.max_speed < scene.behavior.max_speed


def test_scenes_command_prints_the_descriptions():
    out = subprocess.run([sys.executable, "-m", "cloth_tui", "scenes"], capture_output=True,
                         text=True, check=True).stdout
    for name, path in builtin_scenes().items():
        doc = path.read_text(encoding="utf-8").splitlines()[0].lstrip("# ").strip()
        assert any(line.split()[0] == name and doc in line for line in out.splitlines())
