"""Coulomb friction holds draped sheets where the contact force allows (issue 13 item 1).

The slope (20°, friction 1 holds, 0 slides) is tested with the colliders
(test_colliders.py: test_sheet_stays_on_a_20_degree_slope_with_friction_1_and_slides_with_0);
the kernel's static/kinetic rule on single particles there too."""

import numpy as np
import pytest

from cloth_tui.scene_files import load
from cloth_tui.sim.run.runner import Simulation
from ..helpers import run


def settled(name, seconds=10.0, **keys):
    s = load(name)
    for k, v in keys.items():
        s = s.with_value(k.replace("__", "."), v)
    sim = Simulation(s)
    run(sim, int(round(seconds * s.behavior.frame_rate)))
    x = sim.state.x
    centroid = x.mean(axis=0)
    return sim, x, float(np.hypot(centroid[0], centroid[2]))  # objects sit on the y axis


@pytest.fixture(scope="module")
def sphere():
    # 15 s: hpbd's drape folds its skirt corners until about 12 s (pbd's until about 8)
    return settled("sphere", seconds=15.0)


def test_sheet_draped_on_the_sphere_comes_to_rest_on_it(sphere):
    sim, x, off_axis = sphere
    st = sim.stats()
    assert st.finite and st.max_speed < 0.01
    assert off_axis < 0.02
    assert st.penetration <= sim.scene.scene.thickness + 1e-3


def test_without_friction_the_sheet_slides_off_the_sphere(sphere):
    sim, x, off_axis = settled("sphere", scene__friction=0.0)
    floor = sim.scene.scene.floor_height
    assert off_axis > 0.3  # left the sphere (radius 0.25 m)
    assert (x[:, 1] < floor + 0.02).mean() > 0.9  # and lies on the floor
    held = sphere[1]
    assert (held[:, 1] < floor + 0.02).mean() < 0.05


def test_box_holds_its_drape():
    sim, x, off_axis = settled("box")
    st = sim.stats()
    assert st.finite and st.max_speed < 0.01
    assert off_axis < 0.02
    assert x[:, 1].min() > sim.scene.scene.floor_height + 0.1  # hangs, does not slide down
    assert st.penetration <= sim.scene.scene.thickness + 1e-3
