"""The [[objects]] shapes as the scene knows them: each shape's own keys, their checks and
the original's single-object placement. Light enough for the scene schema to read without
importing the physics; the simulation's shapes (sim/collision/shapes/, one module each: the
distance, the render mesh, the bake's prim) take their keys from here, so each is declared
once.

Adding a shape: its entry here (and in SHAPES) and its module under sim/collision/shapes/.
"""

from __future__ import annotations

import dataclasses
import math
from dataclasses import dataclass, field
from typing import Callable

from .scene_keys import SceneError, key, vec3

# Keys several shapes share (one declaration each: SceneObject has one field per name)
RADIUS_KEY = key(0.25, "radius", unit="m", lo=0.0, lo_open=True, hi=1e3)
AXIS_KEY = vec3([1.0, 0.0, 0.0], "axis direction", nonzero=True)
SINGLE_TILT_DEG = 20.0  # the single `scene.object = "plane"` is tilted this much about x


def default_of(declaration):
    """The default value of a key declaration (scene_keys.key)."""
    if declaration.default_factory is not dataclasses.MISSING:
        return declaration.default_factory()
    return declaration.default


def _no_check(obj, where: str) -> None:
    """A shape whose keys' own ranges are all its checks."""


@dataclass(frozen=True)
class ShapeKeys:
    """One shape as the scene knows it. `keys`: its own [[objects]] keys, name → a
    scene_keys.key declaration; `single_object`: scene.object's placement (SceneObject keys),
    None where the original had no such object; `exclusive_keys`: keys no other shape may
    set (a mesh's file), `plural` naming the shape in that message; `check(obj, where)`:
    raises SceneError when a validated SceneObject's keys do not make this shape."""
    name: str
    keys: dict
    single_object: dict | None = None
    exclusive_keys: tuple = ()
    plural: str = ""
    check: Callable[..., None] = field(default=_no_check)


def _check_box(obj, where: str) -> None:
    if min(obj.size) < 0.0:
        raise SceneError(f"{where}: a box's size {list(obj.size)} has a negative side")


def _check_capsule(obj, where: str) -> None:
    if (obj.normal != default_of(PLANE.keys["normal"])
            or obj.size != default_of(BOX.keys["size"])):
        raise SceneError(f"{where}: a capsule takes `axis` (direction) and `length` "
                         "(m), not `normal` and `size` (older files put the axis in normal "
                         "and the length in size[1]); move them to axis and length")


def _check_mesh(obj, where: str) -> None:
    if obj.path == "":
        raise SceneError(f"{where}: a mesh needs `path`, its surface file")


def _check_torus(obj, where: str) -> None:
    # A tube as wide as the ring closes the hole and meets itself: a spindle, not a ring.
    if obj.minor_radius >= obj.major_radius:
        raise SceneError(f"{where}: a torus's minor_radius {obj.minor_radius:g} m must be "
                         f"less than its major_radius {obj.major_radius:g} m")


SPHERE = ShapeKeys(
    "sphere", {"radius": RADIUS_KEY},
    # the original's: radius 0.25 resting on the floor (−0.5)
    single_object=dict(center=[0.0, -0.25, 0.0], radius=0.25))
BOX = ShapeKeys(
    "box", {"size": vec3([0.5, 0.2, 0.5], "sides along x, y and z (axis-aligned)", unit="m")},
    single_object=dict(center=[0.0, 0.0, 0.0], size=[0.5, 0.2, 0.5]), check=_check_box)
PLANE = ShapeKeys(
    "plane", {"normal": vec3([0.0, 1.0, 0.0], "normal (the centre is a point on it)",
                             nonzero=True)},
    # the original's: through the origin, tilted about x (downhill is +z)
    single_object=dict(center=[0.0, 0.0, 0.0],
                       normal=[0.0, math.cos(math.radians(SINGLE_TILT_DEG)),
                               math.sin(math.radians(SINGLE_TILT_DEG))]))
CAPSULE = ShapeKeys(
    "capsule", {"radius": RADIUS_KEY, "axis": AXIS_KEY,
                "length": key(0.5, "length of the axis segment (the capsule's cylinder part)",
                              unit="m", lo=0.0, hi=1e3)},
    # the original's: lying along x under the sheet's centre
    single_object=dict(center=[0.0, -0.1, 0.0], radius=0.15, length=0.5,
                       axis=[1.0, 0.0, 0.0]),
    check=_check_capsule)
MESH = ShapeKeys(
    "mesh", {
        "path": key("", "STL, OBJ, PLY or VTK surface file, relative to the scene file"),
        "scale": key(1.0, "factor on the file's coordinates", lo=0.0, lo_open=True, hi=1e3),
        "rotation": vec3([0.0, 0.0, 0.0], "rotation about x, then y, then z (about the "
                         "file's origin, which `center` places)", unit="°"),
    },
    exclusive_keys=("path",), plural="meshes", check=_check_mesh)
CYLINDER = ShapeKeys(
    "cylinder", {"radius": RADIUS_KEY, "axis": AXIS_KEY,
                 "height": key(0.5, "height along its axis (flat ends)", unit="m", lo=0.0,
                               lo_open=True, hi=1e3)})
TORUS = ShapeKeys(
    "torus", {"axis": AXIS_KEY,
              "major_radius": key(0.25, "radius of the circle the tube's centre follows",
                                  unit="m", lo=0.0, lo_open=True, hi=1e3),
              "minor_radius": key(0.08, "radius of the tube (less than major_radius)",
                                  unit="m", lo=0.0, lo_open=True, hi=1e3)},
    check=_check_torus)

# In the order of the simulation's shape codes (sim/collision/shapes/)
SHAPES: dict[str, ShapeKeys] = {s.name: s for s in (SPHERE, BOX, PLANE, CAPSULE, MESH,
                                                    CYLINDER, TORUS)}


def names() -> tuple[str, ...]:
    return tuple(SHAPES)


def single_object_names() -> tuple[str, ...]:
    """The shapes `scene.object` offers (those with the original's placement)."""
    return tuple(name for name, s in SHAPES.items() if s.single_object is not None)


def object_keys() -> list[tuple[str, str, dataclasses.Field]]:
    """(name, type, declaration) of every shape's own keys, each once, in the registry's
    order; a key several shapes share is one declaration (all of them name the same one),
    its help naming them."""
    seen: dict[str, tuple[dataclasses.Field, list[str]]] = {}
    for s in SHAPES.values():
        for name, declaration in s.keys.items():
            if name in seen and seen[name][0] is not declaration:
                raise TypeError(f"shapes declare `{name}` twice: {seen[name][1]} and "
                                f"{s.name} must share one declaration")
            seen.setdefault(name, (declaration, []))[1].append(s.name)
    out = []
    for name, (declaration, users) in seen.items():
        meta = dict(declaration.metadata)
        meta["doc"] = f"{', '.join(users)}: {meta['doc']}"
        declared = dataclasses.field(default=declaration.default,
                                     default_factory=declaration.default_factory,
                                     metadata=meta)
        out.append((name, type(default_of(declaration)).__name__, declared))
    return out


def check_object(obj, where: str) -> None:
    """The shape's own checks of one validated SceneObject, and that it sets no key another
    shape keeps to itself; raises scene_keys.SceneError."""
    shape = SHAPES.get(obj.type)
    if shape is None:
        raise SceneError(f"{where}: unknown object type {str(obj.type)[:40]!r}; the shapes "
                         f"are {', '.join(SHAPES)}")
    for other in SHAPES.values():
        if other is shape:
            continue
        for name in other.exclusive_keys:
            if getattr(obj, name) != default_of(other.keys[name]):
                raise SceneError(f"{where}: `{name}` is for {other.plural}, not a {obj.type}")
    shape.check(obj, where)
