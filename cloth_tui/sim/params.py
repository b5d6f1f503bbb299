"""The values a step's stages read every substep: the forces' strengths, friction, damping
and the solver's numbers (as Warp's `model.gravity` and `Control`).

A step (pipeline.build) holds one StepParams and its stages read it when they run, so a change of
these values is an assignment (`assign`) that the next substep sees; the masses (cloth.mass, a
material's density) and all of a material's numbers (α per constraint, damping) are the model's,
refitted in place (model.refitted, Step.retune). Nothing is rebuilt, and the adaptive substeps,
the kernels' thread choice and the divergence guard go on. What a step *is* (which stages run, on
which particles and constraints) is the scene's structure: the scene with every parameter reduced
to what decides whether its stage exists (wind at 3 or 5 m/s is the same step; at 0 m/s it has no
wind stage). Two scenes of the same structure (`same_structure`) run the same stages, so only a
change of structure rebuilds the step.
"""

from __future__ import annotations

import dataclasses
import math
from dataclasses import dataclass, field
from typing import TYPE_CHECKING, Any, Callable

from ..materials.section import MaterialSection
from ..scene_keys import SECTIONS

if TYPE_CHECKING:
    from ..scene import Scene


def _positive(value: float) -> bool:
    return value > 0


def _irrelevant(value: Any) -> None:
    return None


def _param(key: str, default: Any, stage: Callable[[Any], Any] = _irrelevant):
    """A StepParams field that takes scene key `key`; `stage`: what of its value decides
    whether the step has the stage that reads it (nothing, for most)."""
    return field(default=default, metadata={"key": key, "stage": stage})


@dataclass
class StepParams:
    """What the stages read each substep. Assigned only between frames, on the thread that
    steps (the simulation's), so a substep never sees half a change. The defaults are the
    schema's, Scene()'s (a test holds them to it). Each field names the one scene key it
    takes."""
    gravity: float = _param("forces.gravity_strength", 9.81, _positive)  # m/s², downward (−y)
    wind_speed: float = _param("forces.wind_strength", 5.0, _positive)  # m/s
    wind_direction: tuple = _param("forces.wind_direction", (0.0, 0.0, 1.0))  # unit vector
    wind_mode: str = _param("forces.wind_mode", "constant")
    custom_strength: float = _param("forces.custom_strength", 10.0, _positive)  # m/s²
    custom_rate: float = _param("forces.custom_rate", 0.5)  # Hz
    rain_strength: float = _param("forces.rain_strength", 0.01, _positive)  # m
    rain_rate: float = _param("forces.rain_rate", 20.0, _positive)  # drops/s
    friction: float = _param("scene.friction", 0.9)  # μs of the floor, objects without their own
    damping: float = _param("behavior.damping", 0.03)  # share of velocity lost per 18 ms
    compliance: float = _param("behavior.compliance", 1e-8)  # m/N, xpbd without a material
    iterations: int = _param("behavior.iterations", 4)  # constraint passes per substep
    max_speed: float = _param("behavior.max_speed", 50.0)  # m/s
    stiffness: float = _param("behavior.stiffness", 2000.0)  # N/m, springs
    spring_damping: float = _param("behavior.spring_damping", 0.5)  # N·s/m, springs
    object_friction: tuple = ()     # each [[objects]] entry's own μs, −1: the scene's

    def __post_init__(self) -> None:
        self.wind_direction = unit(self.wind_direction)

    @classmethod
    def of(cls, scene: Scene) -> "StepParams":
        return cls(**_values(scene))

    def assign(self, scene: Scene) -> None:
        """Take `scene`'s values (one of the same structure as the step's)."""
        for name, value in _values(scene).items():
            setattr(self, name, value)


_KEYED = [(f.name, f.metadata["key"]) for f in dataclasses.fields(StepParams)
          if "key" in f.metadata]

# Each parameter key, and what of its value decides whether the step has its stage: the
# StepParams fields' keys, and the masses, which the model holds (model.refitted).
PARAMETER_KEYS: dict[str, Callable[[Any], Any]] = {
    **{f.metadata["key"]: f.metadata["stage"] for f in dataclasses.fields(StepParams)
       if "key" in f.metadata},
    "cloth.mass": _irrelevant,  # the model's masses, written in place (model.refitted)
}


def unit(direction) -> tuple:
    x, y, z = (float(v) for v in direction)
    n = math.sqrt(x * x + y * y + z * z)
    return (x / n, y / n, z / n)


def _values(scene: Scene) -> dict[str, Any]:
    values = {name: scene.get(key) for name, key in _KEYED}
    values["wind_direction"] = unit(values["wind_direction"])
    values["object_friction"] = tuple(o.friction for o in scene.objects)
    return values


@dataclass(frozen=True)
class FrictionSource:
    """Where a collider reads its μs each substep: an [[objects]] entry's own, or (index
    −1, the floor and scene.object, or an entry without one) the scene's."""
    params: StepParams
    index: int = -1

    def value(self) -> float:
        p = self.params
        own = p.object_friction[self.index] if self.index >= 0 else -1.0
        return own if own >= 0 else p.friction


def same_structure(a: Scene, b: Scene) -> bool:
    """Whether a step built for `a` runs `b` once given b's StepParams: the scenes differ
    at most in parameters, and those alike in what decides whether their stages exist."""
    if (without_friction(a.objects) != without_friction(b.objects) or a.pins != b.pins
            or _material_part(a) != _material_part(b)):
        return False
    for section in SECTIONS:
        if section == "appearance":
            continue  # the renderer's alone: no stage reads it
        sa, sb = getattr(a, section), getattr(b, section)
        if sa == sb:
            continue
        for f in dataclasses.fields(sa):
            va, vb = getattr(sa, f.name), getattr(sb, f.name)
            if va != vb:
                decides = PARAMETER_KEYS.get(f"{section}.{f.name}")
                if decides is None or decides(va) != decides(vb):
                    return False
    return True


def without_friction(objects: list) -> list:
    """[[objects]] with their friction left out (a parameter: StepParams.object_friction)."""
    return [dataclasses.replace(o, friction=-1.0) for o in objects]


def _material_part(scene: Scene) -> MaterialSection | None:
    """What of the scene's material decides its step. Its numbers are α per constraint and
    masses (model.refitted), a measured preset's tension curves and fold rigidities too;
    which constraints there are depends only on whether it has a bending rigidity. Tearing
    by strength is built from the strength and the stretch (its stage, the substeps'
    tolerance), so there every number is part of the structure."""
    section = scene.material
    if section is None or (scene.behavior.tear and section.material.tear_strength is not None):
        return section
    m = section.material
    numbers = dataclasses.replace(m, areal_density=0.0, stretch_warp=0.0, stretch_weft=0.0,
                                  shear=0.0, bending=float(m.bending > 0), damping=0.0,
                                  preset="", stretch_curves=None, bending_by_direction=None)
    return dataclasses.replace(section, table={}, material=numbers)
