"""run/measures.py on hand-made sheets whose answers are known: stretch, the solve error,
energies and the floor numerical damping is measured from."""

from types import SimpleNamespace

import numpy as np
import pytest

from cloth_tui.scene import Scene
from cloth_tui.sim.run import measures
from cloth_tui.sim.run.runner import Simulation


def three_edges():
    """Edges 0-1 stretched 10 %, 1-2 compressed 5 %, 2-3 stretched 50 %, each of rest 1 m."""
    x = np.array([[0.0, 0, 0], [1.1, 0, 0], [2.05, 0, 0], [3.55, 0, 0]])
    model = SimpleNamespace(edges=np.array([[0, 1], [1, 2], [2, 3]], np.int64),
                            rest_length=np.ones(3), num_constraints=3)
    return model, x


def test_stretch_is_the_max_and_mean_of_the_intact_edges_only():
    model, x = three_edges()
    worst, mean = measures.stretch(model, x)
    assert worst == pytest.approx(0.5) and mean == pytest.approx((0.1 + 0.05 + 0.5) / 3)
    torn_last = np.array([1, 1, 0], np.uint8)
    worst, mean = measures.stretch(model, x, torn_last)
    assert worst == pytest.approx(0.1) and mean == pytest.approx(0.075)


def test_a_nan_position_shows_as_nan_stretch_and_error():
    model, x = three_edges()
    x[1, 0] = np.nan
    assert np.isnan(measures.stretch(model, x)[0])
    assert np.isnan(measures.solve_error(model, x, np.ones(3, np.uint8), None, 0.0))
    assert not measures.all_finite(x, np.zeros_like(x))


def test_the_solve_error_is_the_stretch_for_rigid_constraints_and_zero_at_equilibrium():
    model, x = three_edges()
    alive = np.ones(3, np.uint8)
    # α = 0 (pbd): the rigid constraint's equilibrium is its rest length
    assert measures.solve_error(model, x, alive, None, 0.0) == pytest.approx(0.5)
    # a compliant constraint whose multiplier balances its stretch: C = α̃λ leaves nothing
    alpha_tilde = np.full(3, 0.01)
    c = model.rest_length - np.array([1.1, 0.95, 1.5])
    assert measures.solve_error(model, x, alive, c / alpha_tilde, alpha_tilde) == \
        pytest.approx(0.0, abs=1e-12)
    half = 0.5 * c / alpha_tilde
    assert measures.solve_error(model, x, alive, half, alpha_tilde) == pytest.approx(0.25)


def test_per_constraint_broadcasts_one_value_and_refuses_a_wrong_count():
    assert measures.per_constraint(0.5, 3).tolist() == [0.5, 0.5, 0.5]
    with pytest.raises(ValueError, match="one value per constraint"):
        measures.per_constraint(np.ones(2), 3)


def test_energies_of_a_sheet_at_rest_and_moving():
    scene = Scene().with_values({"cloth.resolution": 4, "cloth.pinned": "none",
                                 "scene.floor": True})
    sim = Simulation(scene)
    model, state = sim.model, sim.state
    mass = float(model.mass.sum())
    assert measures.kinetic_energy(model, state) == 0.0
    state.v[:, 0] = 2.0
    assert measures.kinetic_energy(model, state) == pytest.approx(0.5 * mass * 4.0)
    height = float(np.average(state.x[:, 1], weights=model.mass))
    g = scene.forces.gravity_strength
    assert measures.gravitational_energy(model, state, scene) == pytest.approx(mass * g * height)
    # no pins: the floor's skin bounds how low it can fall; without a floor nothing does
    skin = scene.scene.floor_height + scene.scene.thickness
    assert measures.potential_floor(model, state, scene, None, None) == \
        pytest.approx(g * skin * mass)
    no_floor = scene.with_values({"scene.floor": False})
    assert measures.potential_floor(model, state, no_floor, None, None) is None
    weightless = scene.with_values({"forces.gravity": False})
    assert measures.gravitational_energy(model, state, weightless) == 0.0
    # a sheet at rest on its floor still divides by something positive
    assert measures.free_energy(0.0, 0.0, model) > 0.0
