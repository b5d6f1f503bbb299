"""The shape registry: every kind of collision object, one module each, by its scene `type`.

A shape's module holds all of it, for each layer that handles objects (base.Shape), but its
[[objects]] keys and their checks, which the scene schema reads from cloth_tui/object_shapes.py
without importing the physics: the numbers its compiled distance reads (`pack`) and that
distance itself (a plain function sim/contact_kernels.py compiles into its one dispatch, a branch
per shape, since numba needs the branches written out), its render mesh and its USD prim and
how a bake reads it back. `shape_of` refuses a type that is not registered, so no consumer
can fall through to another shape's code.

Adding a shape: its keys in object_shapes.py, a module here with its Shape subclass (a new
`code`), its entry in SHAPES, and its branch in contact_kernels.for_shape and
swept_contacts.distance_at.
"""

from __future__ import annotations

from ....object_shapes import check_object, names, object_keys, single_object_names
from . import box, capsule, cylinder, mesh, plane, sphere, torus
from .base import Shape

__all__ = ["SHAPES", "Shape", "UnknownShapeError", "check_object", "names", "object_keys",
           "shape_of", "single_object_names"]

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


def _check_codes() -> None:
    codes = sorted(s.code for s in SHAPES.values())
    if codes != list(range(len(SHAPES))):
        raise TypeError(f"shape codes must be 0..{len(SHAPES) - 1}, each once: {codes}")
    if tuple(SHAPES) != names():
        raise TypeError(f"the simulation's shapes {tuple(SHAPES)} are not the scene's "
                        f"{names()} (object_shapes.py), in that order")


_check_codes()
