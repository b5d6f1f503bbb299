"""The user's hands on the sheet: a bump, a pin held where the user drops it, a cut. The
runner applies them between frames."""

from __future__ import annotations

import numpy as np

from ...scene_keys import SceneError
from ..effects.tearing import cut_between
from ..model import ClothModel
from ..state import ClothState


def bump(model: ClothModel, state: ClothState, particle: int, displacement, radius: float,
         frame_rate: float) -> None:
    """Push one particle, and its grid neighbours less (Gaussian falloff of `radius`
    spacings), giving them the velocity of moving that far in one frame."""
    d = np.asarray(displacement, dtype=np.float64)
    i0, j0 = divmod(int(particle), model.nx)
    r = int(np.ceil(2 * radius))
    ii, jj = np.meshgrid(np.arange(max(0, i0 - r), min(model.nz, i0 + r + 1)),
                         np.arange(max(0, j0 - r), min(model.nx, j0 + r + 1)), indexing="ij")
    idx = (ii * model.nx + jj).ravel()
    w = np.exp(-((ii - i0) ** 2 + (jj - j0) ** 2).ravel() / (radius * radius))
    w[model.inv_mass[idx] == 0.0] = 0.0
    state.x[idx] += w[:, None] * d
    state.v[idx] += w[:, None] * d * frame_rate


def check_pin_height(scene_settings, position) -> None:
    """Raise SceneError where a pin at `position` would hold its particle inside the floor
    (`scene_settings`: the scene's [scene] section)."""
    s = scene_settings
    if s.floor and float(position[1]) < s.floor_height + s.thickness:
        raise SceneError(f"a pin at height {float(position[1]):.3g} m would hold the "
                         f"particle inside the floor (scene.floor_height = "
                         f"{s.floor_height:g} m + scene.thickness = {s.thickness:g} m)")


def hold(state: ClothState, particle: int, slot: int, position) -> None:
    """Put `particle` at rest at `position`, the anchor of pin `slot` (a new slot: one more
    anchor)."""
    p = np.asarray(position, np.float64)
    if slot == len(state.anchors):
        state.anchors = np.vstack([state.anchors, p])
    state.anchors[slot] = p
    state.x[particle] = state.x_prev[particle] = p
    state.v[particle] = 0.0


def cut(model: ClothModel, state: ClothState, p0: int, p1: int) -> int:
    """Cut the sheet between two particles (tearing.cut_between); returns how many
    constraints were cut, 0 where a particle is not on the sheet."""
    n = model.num_particles
    if not (0 <= int(p0) < n and 0 <= int(p1) < n):
        return 0
    return cut_between(model, state, int(p0), int(p1))
