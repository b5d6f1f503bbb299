"""springs' linearised backward Euler (solvers/springs/implicit_euler.py) on one spring
whose implicit step is known in closed form."""

import numpy as np
import pytest

from cloth_tui.sim.solvers.springs.implicit_euler import solve_implicit_euler

MASS, K, REST = 0.5, 200.0, 1.0


def one_spring_step(d: float, v: float, h: float, alive: int = 1):
    """Particle 0 held at the origin, particle 1 at REST + d along x moving at v; one step.
    Returns (x, v) of particle 1 and the CG iterations used."""
    x = np.array([[0.0, 0, 0], [REST + d, 0, 0]])
    vel = np.array([[0.0, 0, 0], [v, 0, 0]])
    accel = np.zeros((2, 3))
    accel[1, 0] = -K * d / MASS * alive  # the spring's force, as the runner's forces leave it
    mass = np.full(2, MASS)
    free = np.array([0, 1], np.uint8)
    edges = np.array([[0, 1]], np.int64)
    scratch = [np.zeros((2, 3)) for _ in range(6)]  # dv, r, z, p, q, diag
    dirs, tension = np.zeros((1, 3)), np.zeros(1)
    its = solve_implicit_euler(x, vel, accel, mass, free, edges, np.array([REST]),
                               np.array([alive], np.uint8), K, 0.0, 0.0, h, dirs, tension,
                               *scratch, 1e-12, 50)
    return x[1], vel[1], its


@pytest.mark.parametrize("h", [1e-3, 0.05, 1.0])
def test_one_spring_takes_the_closed_form_implicit_step(h):
    # along the spring the system is linear: (m + h²k) Δv = h (−k d − h k v)
    d, v = 0.1, 0.3
    dv = h * (-K * d - h * K * v) / (MASS + h * h * K)
    x1, v1, its = one_spring_step(d, v, h)
    assert v1[0] == pytest.approx(v + dv, rel=1e-9)
    assert x1[0] == pytest.approx(REST + d + h * (v + dv), rel=1e-9)
    assert np.all(v1[1:] == 0.0) and its >= 1


def test_the_step_damps_however_long_it_is():
    # explicit Euler grows without bound past h·ω = 2; the implicit step's energy only falls
    h = 10.0 * np.sqrt(MASS / K)
    d, v = 0.1, 0.0
    energy = 0.5 * K * d * d
    for _ in range(20):
        x1, v1, _ = one_spring_step(d, v, h)
        d, v = x1[0] - REST, v1[0]
        now = 0.5 * K * d * d + 0.5 * MASS * v * v
        assert now < energy
        energy = now


def test_the_held_particle_and_a_torn_spring_stay_put():
    x1, v1, _ = one_spring_step(0.1, 0.0, 0.01, alive=0)
    assert x1[0] == pytest.approx(REST + 0.1) and v1[0] == 0.0
