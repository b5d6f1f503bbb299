"""The NumPy baseline must compute the same step as the compiled one, or the bench's
speed-up would compare different work."""

import numpy as np
import pytest

from cloth_tui.bench.numpy_step import NumpyStep
from cloth_tui.bench.step_bench import bare_scene
from cloth_tui.sim import pipeline
from cloth_tui.sim.model import build_model
from cloth_tui.sim.state import ClothState


@pytest.mark.parametrize("n", [5, 12, 17])
def test_numpy_baseline_matches_compiled_step(n):
    scene = bare_scene(n, iterations=3)
    model = build_model(scene.cloth, scene.behavior)
    step = pipeline.build(scene, model)
    a, b = ClothState.from_model(model), ClothState.from_model(model)
    ref = NumpyStep(model, step.h, 3, scene.behavior.damping, 9.81, scene.behavior.max_speed)
    for _ in range(50):
        step.substep(a)
        ref.substep(b.x, b.x_prev, b.v, b.anchors)
    assert np.abs(a.x - model.rest_positions).max() > 1e-3  # it did move
    np.testing.assert_allclose(b.x, a.x, atol=1e-9)
    np.testing.assert_allclose(b.v, a.v, atol=1e-6)
