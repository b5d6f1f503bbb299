"""What every shape provides, for each layer that handles objects (see the package's
docstring); the parts that are the same for all shapes are written here once.

A shape's [[objects]] keys and their checks are declared in cloth_tui/object_shapes.py,
which the scene schema reads; `keys` and `single_object` here are those.

A shape's *parameters* are the values that say what the object is, apart from where it is:
a sphere's {"radius"}, a box's {"size"}, ... (`parameter_kinds` names them and how each is
recorded in a bake). They are what an ObjectPose carries, what the renderer meshes, what a
bake records; `pack` turns them into the numbers the compiled distance reads after the
centre. Nothing here imports numba, VTK or USD: the renderer and the bake writer pass in
the modules they have loaded.
"""

from __future__ import annotations

import math
from dataclasses import dataclass
from typing import Any, Callable

import numpy as np


MAX_LENGTH = 1e6      # m: any object dimension or position beyond this is not a scene's
MIN_DIRECTION = 1e-6  # a normal or axis shorter than this gives no direction

# How a parameter is recorded on a bake's object prim (cloth_tui:<name>) and checked when read
LENGTH = "length"        # a float in 0..MAX_LENGTH, m
SIDES = "sides"          # three floats in 0..MAX_LENGTH, m
DIRECTION = "direction"  # three finite floats, a unit vector when written
SURFACE = "surface"      # triangles: the shape's own prim holds them (the mesh)


AT_CENTRE = 1e-12  # m: a point this close to a centre or axis has no normal of its own


class ShapeValueError(ValueError):
    """A parameter read back from a bake that a cloth-tui bake never holds."""


@dataclass(frozen=True)
class KernelInputs:
    """What a collider hands the compiled distance for one object: `packed`, the numbers
    after the centre; `grid` and `gradient`, a distance grid (the mesh; other shapes get
    NO_GRID, which their branch never reads). `parameters` are the pose's."""
    parameters: dict
    packed: tuple
    grid: np.ndarray
    gradient: np.ndarray


NO_GRID = np.zeros((2, 2, 2))
NO_GRADIENT = np.zeros((2, 2, 2, 3))


class Shape:
    """One kind of object. Subclasses set the class attributes and the methods marked."""

    name = ""            # the scene's `type`
    code = -1            # its branch in the compiled dispatch (contact_kernels.for_shape)
    keys: dict = {}      # its own [[objects]] keys (object_shapes.ShapeKeys.keys)
    parameter_kinds: dict = {}  # the pose's parameters: name → LENGTH, SIDES, ...
    single_object: dict | None = None  # scene.object's placement (object_shapes.ShapeKeys)
    sided = False        # particles keep the side they start on (an infinite plane)
    smooth = True        # the renderer shades it smoothly (a box has flat faces)
    faint = False        # drawn fainter (a plane spans the view)
    # the distance, a plain function numba compiles into the dispatch:
    # distance(qx, qy, qz, p, side, grid, gradient) → (d, nx, ny, nz) for q relative to the
    # centre, with p[0:3] the centre and p[3:] the packed parameters
    distance: Callable = staticmethod(lambda *a: None)

    # -- simulation -----------------------------------------------------------------------
    def parameters(self, obj) -> dict:
        """The pose's parameters of a (validated) SceneObject of this type."""
        raise NotImplementedError

    def pack(self, parameters: dict) -> tuple:
        """The numbers the compiled distance reads after the centre."""
        raise NotImplementedError

    def kernel_inputs(self, obj, spacing: float, thickness: float, where: str) -> KernelInputs:
        """Everything a collider needs for `obj` on a sheet of this particle spacing."""
        return self.inputs_of(self.parameters(obj))

    def inputs_of(self, parameters: dict) -> KernelInputs:
        """The kernel inputs of a shape given by its parameters (not the mesh's: a grid)."""
        return KernelInputs(parameters, self.pack(parameters), NO_GRID, NO_GRADIENT)

    def check_scene(self, objects: list) -> None:
        """A check of all of a scene's objects of this type together, before any is built;
        `objects` are (where, SceneObject) pairs."""

    def sides(self, q: np.ndarray, packed: tuple) -> np.ndarray:
        """±1, the side of the shape each point (relative to the centre) is on: sided only."""
        raise NotImplementedError(f"a {self.name} has no sides")

    # -- rendering ------------------------------------------------------------------------
    def render_mesh(self, pv, parameters: dict):
        """A PyVista mesh of the shape centred at the origin (the actor's position places it)."""
        raise NotImplementedError

    def render_key(self, parameters: dict) -> tuple:
        """Equal for parameters that draw the same mesh: the renderer re-meshes on a change."""
        return tuple((k, _hashable(v)) for k, v in sorted(parameters.items()))

    # -- bakes ----------------------------------------------------------------------------
    def define_usd(self, usd, stage, path: str, parameters: dict) -> None:
        """The shape's prim at `path`, in the object's frame; `usd` holds pxr's Gf, Sdf,
        UsdGeom and Vt."""
        raise NotImplementedError

    def write_usd_parameters(self, usd, prim, parameters: dict) -> None:
        """cloth_tui:type and each parameter as a cloth_tui:<name> attribute of the object's
        prim, what read_usd reads back exactly."""
        Sdf, Gf = usd.Sdf, usd.Gf
        prim.CreateAttribute("cloth_tui:type", Sdf.ValueTypeNames.String,
                             custom=True).Set(self.name)
        for name, kind in self.parameter_kinds.items():
            if kind == LENGTH:
                prim.CreateAttribute(f"cloth_tui:{name}", Sdf.ValueTypeNames.Double,
                                     custom=True).Set(float(parameters[name]))
            elif kind in (SIDES, DIRECTION):
                prim.CreateAttribute(f"cloth_tui:{name}", Sdf.ValueTypeNames.Double3,
                                     custom=True).Set(Gf.Vec3d(*map(float, parameters[name])))

    def read_usd(self, prim) -> dict:
        """The parameters recorded on an object's prim, checked; ShapeValueError says what
        is wrong."""
        out = {}
        for name, kind in self.parameter_kinds.items():
            attr = prim.GetAttribute(f"cloth_tui:{name}")
            value = attr.Get() if attr else None
            out[name] = read_value(name, kind, value)
        return out


def read_value(name: str, kind: str, value: Any):
    """One recorded parameter of kind LENGTH, SIDES or DIRECTION, checked."""
    if kind == LENGTH:
        v = finite(value)
        if v is None or not 0.0 <= v <= MAX_LENGTH:
            raise ShapeValueError(f"cloth_tui:{name} is missing or not a length in "
                                  f"0..{MAX_LENGTH:g} m")
        return v
    v = vector(value)
    if v is None or (kind == SIDES and min(v) < 0.0):
        raise ShapeValueError(f"cloth_tui:{name} is missing or not three finite numbers "
                              f"within ±{MAX_LENGTH:g}" + (", none negative"
                                                           if kind == SIDES else ""))
    if kind == DIRECTION:
        if math.hypot(*v) < MIN_DIRECTION:
            raise ShapeValueError(f"cloth_tui:{name} is too short to give a direction")
        return unit(v)
    return v


def finite(value) -> float | None:
    if isinstance(value, bool):
        return None
    try:
        f = float(value)
    except (TypeError, ValueError, OverflowError):
        return None
    return f if math.isfinite(f) else None


def vector(value) -> tuple | None:
    """Three finite numbers within ±MAX_LENGTH, or None."""
    try:
        v = tuple(float(x) for x in value)
    except (TypeError, ValueError, OverflowError):
        return None
    if len(v) != 3 or not all(math.isfinite(x) and abs(x) <= MAX_LENGTH for x in v):
        return None
    return v


def unit(v) -> tuple:
    """v normalised, as a tuple of floats (the scene refuses directions too short for it)."""
    a = np.asarray(v, dtype=np.float64)
    return tuple(float(x) for x in a / np.linalg.norm(a))


def turn_from_z(usd, direction):
    """The orientation (a float quaternion) that turns +z onto `direction`: USD's capsule
    and cylinder stand along their `axis` token, z here, and are turned onto the shape's."""
    Gf = usd.Gf
    return Gf.Quatf(Gf.Rotation(Gf.Vec3d(0, 0, 1), Gf.Vec3d(*direction)).GetQuat())


def _hashable(v):
    return tuple(map(float, v)) if isinstance(v, (tuple, list, np.ndarray)) else v
