import numpy as np

from cloth_tui.scene import Scene
from cloth_tui.sim.effects import stages
from cloth_tui.sim.solvers.xpbd import verlet
from cloth_tui.sim.model import build_model


def test_damping_is_independent_of_timestep():
    # Velocity kept after 36 ms is the same whether taken in 2 steps or 8.
    assert stages.damping_factor(0.03, 0.018) ** 2 == np.float64(0.97 ** 2)
    np.testing.assert_allclose(stages.damping_factor(0.03, 0.0045) ** 8, 0.97 ** 2)


def test_speed_clamp_limits_prediction():
    s = Scene()
    s.cloth.resolution = 3
    m = build_model(s.cloth, s.behavior)
    x = m.rest_positions.copy()
    v = np.zeros_like(x)
    v[4] = (1000.0, 0.0, 0.0)
    xp, acc = x.copy(), np.zeros_like(x)
    verlet.integrate_verlet(x, xp, v, acc, m.inv_mass, 0.01, 1.0, 50.0)
    assert abs((x[4, 0] - xp[4, 0]) / 0.01 - 50.0) < 1e-9
