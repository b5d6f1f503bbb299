"""The shape registry: every kind of collision object, one module each, by its scene `type`.

A shape's module holds all of it, for each layer that handles objects (base.Shape): its
[[objects]] keys and their checks, the numbers its compiled distance reads (`pack`) and that
distance itself (a plain function sim/contact_kernels.py compiles into its one dispatch, a branch
per shape, since numba needs the branches written out), its render mesh and its USD prim and
how a bake reads it back. `shape_of` refuses a type that is not registered, so no consumer
can fall through to another shape's code.

Adding a shape: a module here with its Shape subclass (a new `code`), its entry in SHAPES,
and its branch in contact_kernels.for_shape and swept_contacts.distance_at.
"""

from __future__ import annotations

import dataclasses

from . import box, capsule, cylinder, mesh, plane, sphere, torus
from . import base
from .base import Shape

SHAPES: dict[str, Shape] = {s.name: s for s in (sphere.SHAPE, box.SHAPE, plane.SHAPE,
                                                 capsule.SHAPE, mesh.SHAPE, cylinder.SHAPE,
                                                 torus.SHAPE)}


class UnknownShapeError(ValueError):
    """A type no shape is registered for."""


def shape_of(name: str) -> Shape:
    try:
        return SHAPES[name]
    except (KeyError, TypeError):
        raise UnknownShapeError(f"unknown object type {str(name)[:40]!r}; the shapes are "
                                f"{', '.join(SHAPES)}") from None


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
        field = dataclasses.field(default=declaration.default,
                                  default_factory=declaration.default_factory, metadata=meta)
        out.append((name, type(base.default_of(declaration)).__name__, field))
    return out


def check_object(obj, where: str) -> None:
    """The shape's own checks of one validated SceneObject, and that it sets no key another
    shape keeps to itself; raises scene_keys.SceneError."""
    from ....scene_keys import SceneError
    shape = shape_of(obj.type)
    for other in SHAPES.values():
        if other is shape:
            continue
        for name in other.exclusive_keys:
            if getattr(obj, name) != base.default_of(other.keys[name]):
                raise SceneError(f"{where}: `{name}` is for {other.plural}, not a {obj.type}")
    shape.check(obj, where)


def _check_codes() -> None:
    codes = sorted(s.code for s in SHAPES.values())
    if codes != list(range(len(SHAPES))):
        raise TypeError(f"shape codes must be 0..{len(SHAPES) - 1}, each once: {codes}")


_check_codes()
