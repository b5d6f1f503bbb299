"""What new settings rebuild: the model (a new sheet, so a new run) or only the step. Read by
the runner when it is handed a scene."""

from __future__ import annotations

import dataclasses
from typing import TYPE_CHECKING

from ..model import MODEL_KEYS, uses_tethers

if TYPE_CHECKING:
    from ...scene import Scene


def scene_material(scene: Scene):
    """The scene's material (materials.schema.Material), None for the original's keys."""
    return None if scene.material is None else scene.material.material


def needs_new_model(scene: Scene, old: Scene) -> bool:
    """Whether going from `old` to `scene` changes the sheet itself: a model key, the pins,
    the material, or whether the solver uses tethers."""
    changed = {(s, f.name) for s in ("cloth", "behavior")
               for f in dataclasses.fields(getattr(scene, s))
               if getattr(getattr(scene, s), f.name) != getattr(getattr(old, s), f.name)}
    return bool(changed & MODEL_KEYS) or scene.pins != old.pins \
        or scene.material != old.material \
        or uses_tethers(scene.behavior, scene_material(scene)) \
        != uses_tethers(old.behavior, scene_material(old))


def has_energy_source(scene: Scene) -> bool:
    """Whether anything in the scene may add energy to the sheet (besides the user)."""
    f = scene.forces
    return (f.wind or f.custom != "none" or f.rain or scene.behavior.wave
            or (scene.scene.moving and scene.scene.object != "none")
            or any(o.motion != "static" for o in scene.objects)
            or any(g.keys for g in scene.pins))  # moving pin groups
