"""Deterministic snapshots for render tests: an analytic drape instead of a simulation, so
images (and golden baselines) depend on the renderer only, not on physics changes; and the
small helpers that draw them and read the cloth's red back."""

from __future__ import annotations

import dataclasses

import numpy as np

from cloth_tui.scene import Scene
from cloth_tui.sim.protocols import ObjectPose
from cloth_tui.sim.model import build_model
from cloth_tui.sim.run.run_stats import RunStats
from cloth_tui.sim.run.runner import Snapshot


def scene_with(**appearance) -> Scene:
    scene = Scene()
    for k, v in appearance.items():
        scene = scene.with_value(f"appearance.{k}", v)
    return scene


def draped(scene: Scene, sag: float = 0.25, model=None, frame: int = 1,
           objects: tuple = ()) -> Snapshot:
    """The sheet sagging between its corners like the original scene after a second."""
    model = model or build_model(scene.cloth, scene.behavior)
    x = np.array(model.rest_positions, dtype=np.float64)
    width, length = scene.cloth.dimensions()
    u, w = x[:, 0] / (width / 2), x[:, 2] / (length / 2)
    x[:, 1] -= sag * (1 - u * u * w * w) * (1 - 0.3 * (u * u + w * w))
    return Snapshot(x, frame, frame / 60, RunStats(frames=frame), model, scene, tuple(objects))


def with_positions(snap: Snapshot, positions) -> Snapshot:
    return dataclasses.replace(snap, positions=np.asarray(positions))


SPHERE = ObjectPose("sphere", {"radius": 0.25}, (0.0, -0.25, 0.0))


def red_pixels(img: np.ndarray) -> int:
    r, g, b = (img[..., k].astype(int) for k in range(3))
    return int(((r > 110) & (r > 2 * g) & (r > 2 * b)).sum())


def fresh(renderer, snap, size=(320, 240), elevation=None):
    """`snap` drawn by `renderer` at `size` from its home view (at `elevation`, degrees)."""
    renderer.resize(*size)
    renderer.update_scene(snap.scene)
    renderer.reset_camera()
    if elevation is not None:
        renderer.orbit(0.0, elevation - renderer.camera.elevation)
    return renderer.render(snap)


def cloth_red(img):
    """Where `img` shows the red cloth, and the red channel there."""
    r, g, b = (img[..., k].astype(float) for k in range(3))
    mask = (r > 2 * g) & (r > 2 * b) & (r > 40)
    return mask, r[mask]
