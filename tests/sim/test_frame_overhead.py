"""The per-frame work around the step (health checks, the undo copy) allocates nothing that
grows with the sheet: at 128² a masked NumPy check cost 12 % of the frame. (A scene with
colliders still measures penetration in NumPy each frame: not covered here.)"""

import tracemalloc

import numpy as np

from cloth_tui.scene import Scene
from cloth_tui.sim.measures import fastest_free_speed
from cloth_tui.sim.runner import Simulation


def test_fastest_free_speed_ignores_pins_and_sees_nan():
    x = np.zeros((3, 3))
    v = np.array([[0.0, -9.0, 0.0], [1.0, 2.0, -3.0], [0.5, 0.0, 0.0]])
    inv_mass = np.array([0.0, 1.0, 1.0])  # particle 0 is pinned
    assert fastest_free_speed(x, v, inv_mass) == 3.0
    v[2, 1] = np.nan
    assert np.isnan(fastest_free_speed(x, v, inv_mass))
    v[2, 1] = 0.0
    x[0, 2] = np.inf  # even a pinned particle's position counts
    assert np.isnan(fastest_free_speed(x, v, inv_mass))


def test_advance_frame_allocates_no_per_particle_arrays():
    scene = Scene()
    scene.cloth.resolution = 64
    scene.behavior.adaptive = False
    scene.scene.floor = False
    sim = Simulation(scene)
    for _ in range(3):
        sim.advance_frame()
    tracemalloc.start()
    try:
        tracemalloc.reset_peak()
        for _ in range(5):
            sim.advance_frame()
        _, peak = tracemalloc.get_traced_memory()
    finally:
        tracemalloc.stop()
    per_particle_array = 64 * 64 * 3 * 8
    assert peak < per_particle_array / 4
