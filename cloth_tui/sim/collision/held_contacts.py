"""Held particles (pins, pin groups, and both edges of the wave) are never pushed by a
contact: one that starts inside an object's skin, or a sheet held on both sides of a plane
(which cannot be walked around), makes contacts that can never hold. The sheet then tears
itself apart between the object and the pins (a sphere of radius 1000 m around a pinned
sheet, a plane above pinned corners). Such a scene is refused with the
reason, as scene.validate refuses held particles inside the floor; that one is checked there,
since it needs no model. Pin groups with keys are checked along their tracks
(pins.track_times); soft pins not at all, since a contact can push them. A static object is
checked where the scene puts it; a moving one at ORBIT_SAMPLES places along its orbit (one
that swept a 0.1 m sphere over a pinned corner stretched the sheet's constraints to 2.9×
their length and pinned the adaptive substeps at their maximum while it passed)."""

from __future__ import annotations

import dataclasses
from typing import TYPE_CHECKING

import numpy as np

from ...scene_keys import SceneError
from .colliders import ORBIT_PERIOD, Floor, ShapeCollider, build_colliders, scene_objects
from ..effects.forces import wave_rows
from ..model import ClothModel, build_model
from ..params import without_friction
from ..effects.pins import hard_anchors, track_times

if TYPE_CHECKING:
    from ...scene import Scene

WAVE_SAMPLES = 9  # heights of the wave's driven edge checked, from trough to crest
# Places checked along a moving object's orbit (2π · 0.25 m round): 1.2 cm apart. A distance
# changes no faster than the object moves, so a skin that reaches a held particle between two
# of them reaches less than 6 mm past it.
ORBIT_SAMPLES = 128


def check_held_particles(scene: Scene, model: ClothModel) -> None:
    """Raise SceneError naming the first object that holds a held particle in its skin, or
    a plane with held particles on both sides of it."""
    if not len(model.pinned):
        return
    for points in _held_positions(scene, model):
        _check_objects(scene, model, points)


def _check_objects(scene: Scene, model: ClothModel, points: np.ndarray) -> None:
    for where, collider in _objects(scene, model):
        if not collider.moving:
            _check_object(scene, where, collider, collider.center0, points, "")
            continue
        for t in np.arange(ORBIT_SAMPLES) * (ORBIT_PERIOD / ORBIT_SAMPLES):
            _check_object(scene, where, collider, collider.center_at(float(t)), points,
                          f", {t:.3g} s into its orbit")


def _check_object(scene: Scene, where: str, collider: ShapeCollider, center: np.ndarray,
                  points: np.ndarray, when: str) -> None:
    """The check for one object with its centre at `center`; `when` says where on its
    orbit, for a moving one."""
    s = scene.scene
    kind = collider.shape.name
    if collider.shape.sided:
        side = collider.sides(points, center)
        if (side > 0).any() and (side < 0).any():
            raise SceneError(f"{where} (a {kind}{when}) passes between held particles "
                             f"({_held(scene)}): the sheet is held on both sides of a {kind} "
                             "it cannot cross; move it or the sheet")
    collider.center = center  # what signed_distance measures from (a sided shape: each
    d = collider.signed_distance(points)  # point on its own side, none known yet)
    k = int(np.argmin(d))
    if d[k] < s.thickness:
        p = ", ".join(f"{v:.3g}" for v in points[k])
        raise SceneError(f"{where} (a {kind}{when}) encloses a held particle ({_held(scene)}) "
                         f"at ({p}) m: it is within the object's surface + scene.thickness "
                         f"= {s.thickness:g} m, where no contact can push it out; move the "
                         "object or the sheet (cloth.height, cloth.size)")


def held_inputs_differ(a: Scene, b: Scene) -> bool:
    """Whether the check may answer differently for `b` than for `a`: the sheet, its pins,
    the wave's edges or the objects and the floor differ (a change of forces, solver,
    damping or appearance moves no held particle and no object)."""
    return _held_inputs(a) != _held_inputs(b)


def _held_inputs(scene: Scene) -> tuple:
    b = scene.behavior
    return (dataclasses.replace(scene.cloth, mass=0.0, mass_model="area"),
            dataclasses.replace(scene.scene, friction=0.0), without_friction(scene.objects),
            scene.pins, b.wave, b.wave_amplitude, b.seed)


# The held inputs (_held_inputs) of the last scene the check passed. The app checks an edit on
# its own thread, where a refusal keeps its last good settings, before it hands the scene to
# the simulation, which then does not check the same inputs again. One reference, replaced
# whole, so the two threads may read and write it.
_passed: tuple | None = None


def check_scene(scene: Scene, model: ClothModel) -> None:
    """check_held_particles for the model built from `scene` alone (no user pins), unless a
    scene with the same held inputs passed last."""
    global _passed
    inputs = _held_inputs(scene)
    if inputs == _passed:
        return
    check_held_particles(scene, model)
    _passed = inputs


def check_start(scene: Scene) -> None:
    """The same check for a scene that has no simulation yet (the app, before it applies a
    change): a model without tethers is enough, and cheaper."""
    if _held_inputs(scene) == _passed:
        return
    behavior = dataclasses.replace(scene.behavior, tethers=False)
    check_scene(scene, build_model(scene.cloth, behavior, scene.pins))


def _held(scene: Scene) -> str:
    c, b = scene.cloth, scene.behavior
    return (f"cloth.pinned = \"{c.pinned}\"" + (", behavior.wave" if b.wave else "")
            + (", [[pins]]" if scene.pins else ""))


def _held_positions(scene: Scene, model: ClothModel) -> list[np.ndarray]:
    """Where the held particles are: at the start and, for groups with keys, along their
    tracks (pins.track_times); with the wave, with its driven edge at each of several heights
    from trough to crest (the floor check takes its trough). Each set has at most one point
    per particle (signed_distance reads a per-particle side)."""
    b = scene.behavior
    lay = model.pin_layout
    times = track_times(lay.hard) if lay is not None else [0.0]
    places = [hard_anchors(model, float(t)) for t in times]
    if not b.wave or b.wave_amplitude == 0.0:
        return places
    driven = np.isin(model.pinned, wave_rows(model.nx, model.nz)[0])
    out = []
    for anchors in places:
        for dy in np.linspace(-b.wave_amplitude, b.wave_amplitude, WAVE_SAMPLES):
            points = anchors.copy()
            points[driven, 1] += dy
            out.append(points)
    return out


def _objects(scene: Scene, model: ClothModel) -> list[tuple[str, ShapeCollider]]:
    """(key, collider) of every object, the floor left out, in build_colliders' order."""
    colliders = [c for c in build_colliders(scene, model) if not isinstance(c, Floor)]
    return [(where, c) for (where, _), c in zip(scene_objects(scene), colliders, strict=True)]
