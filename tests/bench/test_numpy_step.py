"""The NumPy baseline must compute the same step as the compiled one, or the bench's
speed-up would compare different work."""

import numpy as np
import pytest

from cloth_tui.bench.numpy_step import NumpyStep
from cloth_tui.bench.step_bench import bare_scene
from cloth_tui.sim import pipeline
from cloth_tui.sim.model import build_model
from cloth_tui.sim.state import ClothState


def run_both(n, substeps: int, max_speed: float = 50.0, size=1.0):
    """The compiled and the NumPy bare step side by side from the same start (n particles a
    side, or [nx, nz]); returns both final states and the largest speed any free particle
    reached along the way."""
    scene = bare_scene(n, iterations=3)
    scene.cloth.size = size
    scene.behavior.max_speed = max_speed
    model = build_model(scene.cloth, scene.behavior)
    step = pipeline.build(scene, model)
    a, b = ClothState.from_model(model), ClothState.from_model(model)
    ref = NumpyStep(model, step.h, 3, scene.behavior.damping, 9.81, max_speed)
    top_speed = 0.0
    for _ in range(substeps):
        step.substep(a)
        ref.substep(b.x, b.x_prev, b.v, b.anchors)
        top_speed = max(top_speed, float(np.linalg.norm(a.v, axis=1).max()))
    assert np.abs(a.x - model.rest_positions).max() > 1e-3  # it did move
    return a, b, top_speed


@pytest.mark.parametrize("n", [5, 12, 17])
def test_numpy_baseline_matches_compiled_step(n):
    a, b, top_speed = run_both(n, 50)
    assert top_speed < 50.0  # the ordinary case: the clamp is not reached
    np.testing.assert_allclose(b.x, a.x, atol=1e-9)
    np.testing.assert_allclose(b.v, a.v, atol=1e-6)


@pytest.mark.parametrize("shape, size", [([13, 6], [1.2, 0.5]), ([6, 13], 1.0)])
def test_numpy_baseline_matches_compiled_step_on_a_rectangle(shape, size):
    a, b, _ = run_both(shape, 50, size=size)
    np.testing.assert_allclose(b.x, a.x, atol=1e-9)
    np.testing.assert_allclose(b.v, a.v, atol=1e-6)


@pytest.mark.parametrize("n", [5, 12])
def test_numpy_baseline_matches_compiled_step_at_the_speed_clamp(n):
    # 0.5 m/s is reached within a fraction of a second of falling, so most substeps clamp.
    max_speed = 0.5
    a, b, top_speed = run_both(n, 120, max_speed)
    assert 0.99 * max_speed <= top_speed < 1.1 * max_speed  # reached, and held by the clamp
    np.testing.assert_allclose(b.x, a.x, atol=1e-9)
    np.testing.assert_allclose(b.v, a.v, atol=1e-6)


@pytest.mark.parametrize("n", [5, 12, 17])
def test_serial_peer_matches_compiled_step(n):
    # The bench's serial numba loop must do the project's work, or its ratio means nothing.
    from cloth_tui.bench.serial_step import SerialStep

    scene = bare_scene(n, iterations=3)
    model = build_model(scene.cloth, scene.behavior)
    step = pipeline.build(scene, model)
    a, b = ClothState.from_model(model), ClothState.from_model(model)
    peer = SerialStep(model, step.h, 3, scene.behavior.damping, 9.81, scene.behavior.max_speed)
    for _ in range(50):
        step.substep(a)
        peer.substep(b)
    assert np.abs(a.x - model.rest_positions).max() > 1e-3
    np.testing.assert_allclose(b.x, a.x, atol=1e-9)
    np.testing.assert_allclose(b.v, a.v, atol=1e-6)
