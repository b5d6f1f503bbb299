"""Colliders: contact projection, then Coulomb friction on the substep's whole motion.

Contact (`apply`, and again after the constraints in `pipeline.assemble`'s resolve pass): a
particle closer than `thickness` to an object's surface (signed distance d < thickness) is
moved out along the outward normal n by the depth δ = thickness − d. The contact records δ
(summed over both passes: how far the object pushed this substep) and n.

Friction (`apply_friction`, after the constraint projection and the resolve pass, once per
substep; Macklin, Müller, Chentanez & Kim 2014, "Unified particle physics", §6.1): for a
particle the object pushed by δ > 0 this substep, with Δc the object's displacement,

    Δx  = (x − x_prev) − Δc              the substep's whole motion relative to the object
    Δx⊥ = Δx − (Δx·n) n                  its tangential part
    static   |Δx⊥| < μs·δ :  x ← x − Δx⊥                           (it sticks)
    kinetic  otherwise    :  x ← x − Δx⊥ · min(μk·δ / |Δx⊥|, 1)     (slides, slowed)

δ is the normal measure: a position-based contact's normal impulse is m·δ/h, so μ·δ is
Coulomb's bound μ·|f_n|·h² / m. Because Δx includes what the constraints did, friction
also resists a sheet's own weight dragging its touching part sideways. μs = `friction`,
μk = KINETIC_SHARE · μs: 0 slides freely; 1 holds wherever the tangential pull is at most the
normal push (a sheet on a slope of up to 45°). A moving object carries what sticks to it.

Moving objects follow the original's slow circle (ORBIT_RADIUS, ORBIT_PERIOD).
"""

from __future__ import annotations

import math

import numpy as np

from ..scene import SceneObject
from .jit import kernel
from .params import FrictionSource, StepParams
from .protocols import Collider, ObjectPose
from .shapes import SHAPES, Shape, box, capsule, cylinder, mesh, plane, shape_of, sphere, torus
from .shapes.base import KernelInputs

ORBIT_RADIUS = 0.25   # m, radius of a moving object's horizontal circle
ORBIT_PERIOD = 10.0   # s, one revolution (≈ 0.16 m/s: the original's slow drift)
KINETIC_SHARE = 0.8   # μk / μs: sliding friction a little below sticking (typical of fabric)


# -- kernels --------------------------------------------------------------------------------
# Each shape's distance (signed distance d of a point q relative to the shape's centre, and
# the outward unit normal there) is written once, in its module under sim/shapes/; the
# contact kernel and the penetration measure both call it through for_shape.
_sphere = kernel(inline="always")(sphere.distance)
_box = kernel(inline="always")(box.distance)
_capsule = kernel(inline="always")(capsule.distance)
_plane = kernel(inline="always")(plane.distance)
_mesh = kernel(inline="always")(mesh.distance)
_cylinder = kernel(inline="always")(cylinder.distance)
_torus = kernel(inline="always")(torus.distance)
SPHERE, BOX, CAPSULE, PLANE, MESH, CYLINDER, TORUS = (
    sphere.SHAPE.code, box.SHAPE.code, capsule.SHAPE.code, plane.SHAPE.code, mesh.SHAPE.code,
    cylinder.SHAPE.code, torus.SHAPE.code)
# the codes for_shape has a branch for
DISPATCHED = {SPHERE, BOX, CAPSULE, PLANE, MESH, CYLINDER, TORUS}


@kernel(inline="always")
def _no_shape(qx, qy, qz, p, side, grid, gradient):
    """An unknown code's distance: NaN (ShapeCollider refuses one before any kernel runs)."""
    return math.nan, 0.0, 1.0, 0.0


@kernel(inline="always")
def for_shape(code, body, args):
    """body(distance, args) with the distance function of shape `code` (p[0:3] its centre
    and p[3:] its packed parameters, for a point q relative to the centre; `side` (±1)
    picks the side of a two-sided plane, grid and gradient are a mesh's distance grid).
    The branch is taken once for a whole loop over the sheet, which `body` holds, not once
    a particle: a loop with the distance call fixed is compiled for each shape (measured
    on a 256² sheet above the floor, one contact pass: 0.98 ms with the branch inside the
    loop, 0.11 ms with it outside)."""
    if code == SPHERE:
        return body(_sphere, args)
    if code == BOX:
        return body(_box, args)
    if code == CAPSULE:
        return body(_capsule, args)
    if code == PLANE:
        return body(_plane, args)
    if code == MESH:
        return body(_mesh, args)
    if code == CYLINDER:
        return body(_cylinder, args)
    if code == TORUS:
        return body(_torus, args)
    return body(_no_shape, args)


@kernel(inline="always")
def push_out_of_contact(x, i, d, nx, ny, nz, thickness, depth, normal):
    """Particle i, at distance d along the outward normal n, goes out to the skin's surface
    (`thickness` from the object's); its contact keeps depth[i] += how far and normal[i] = n
    for the friction stage."""
    push = thickness - d
    x[i, 0] += push * nx
    x[i, 1] += push * ny
    x[i, 2] += push * nz
    depth[i] += push
    normal[i, 0] = nx
    normal[i, 1] = ny
    normal[i, 2] = nz


@kernel(inline="always")
def _contacts(distance, args):
    x, inv_mass, side, p, grid, gradient, thickness, depth, normal = args
    cx, cy, cz = p[0], p[1], p[2]
    for i in range(x.shape[0]):
        if inv_mass[i] == 0.0:
            continue
        d, nx, ny, nz = distance(x[i, 0] - cx, x[i, 1] - cy, x[i, 2] - cz, p, side[i], grid,
                                 gradient)
        if d < thickness:
            push_out_of_contact(x, i, d, nx, ny, nz, thickness, depth, normal)


@kernel()
def collide_shape(x, inv_mass, side, code, p, grid, gradient, thickness, depth, normal):
    """Contact projection for one object: a particle inside the skin goes out along the
    normal to the skin's surface; depth[i] += how far, normal[i] = n. side[i] = ±1 is the
    side of a plane the particle started on (an infinite plane cannot be walked around, so
    it keeps it); other shapes ignore it."""
    for_shape(code, _contacts, (x, inv_mass, side, p, grid, gradient, thickness, depth,
                                normal))


@kernel()
def apply_coulomb_friction(x, x_prev, depth, normal, dx, dy, dz, mu_static, mu_kinetic):
    """Static and kinetic friction on each contact's motion relative to the object (see the
    module's docstring); (dx, dy, dz) is the object's displacement this substep. Clears
    `depth` for the next substep."""
    for i in range(x.shape[0]):
        push = depth[i]
        if push == 0.0:
            continue
        depth[i] = 0.0
        nx = normal[i, 0]
        ny = normal[i, 1]
        nz = normal[i, 2]
        rx = x[i, 0] - x_prev[i, 0] - dx
        ry = x[i, 1] - x_prev[i, 1] - dy
        rz = x[i, 2] - x_prev[i, 2] - dz
        rn = rx * nx + ry * ny + rz * nz
        tx = rx - rn * nx
        ty = ry - rn * ny
        tz = rz - rn * nz
        slide = math.sqrt(tx * tx + ty * ty + tz * tz)
        if slide == 0.0:
            continue
        if slide < mu_static * push:
            removed = 1.0  # static: all of the tangential motion
        else:
            removed = min(mu_kinetic * push / slide, 1.0)
        x[i, 0] -= removed * tx
        x[i, 1] -= removed * ty
        x[i, 2] -= removed * tz


@kernel(inline="always")
def _distances(distance, args):
    x, side, p, grid, gradient, out = args
    cx, cy, cz = p[0], p[1], p[2]
    for i in range(x.shape[0]):
        d, _, _, _ = distance(x[i, 0] - cx, x[i, 1] - cy, x[i, 2] - cz, p, side[i], grid,
                              gradient)
        out[i] = d


@kernel()
def signed_distances(x, side, code, p, grid, gradient, out):
    """out[i] = signed distance of point i from the true surface (negative inside), m: the
    same distance function the contact kernel uses."""
    for_shape(code, _distances, (x, side, p, grid, gradient, out))


# -- effects --------------------------------------------------------------------------------
class ShapeCollider:
    """One object of any registered shape (sim/shapes/), static or moving along the orbit:
    its kernel inputs come from its shape, the contact, friction and motion are the same
    for all."""

    def __init__(self, model, shape: Shape, inputs: KernelInputs, center, *,
                 friction: float | FrictionSource, thickness: float, moving: bool = False):
        if shape.code not in DISPATCHED:
            raise ValueError(f"the {shape.name} shape has no branch in for_shape")
        self.name = f"collide_{shape.name}"
        self.shape, self.moving = shape, moving
        self.parameters = inputs.parameters
        self.grid, self.gradient = inputs.grid, inputs.gradient
        self.inv_mass = model.inv_mass
        self.center0 = np.asarray(center, dtype=np.float64)
        self.center = self.center0.copy()
        self.params = np.array([*self.center0, *inputs.packed], dtype=np.float64)
        # μs, or where the step's parameters hold it now
        self._friction = friction if isinstance(friction, FrictionSource) else float(friction)
        self.thickness = float(thickness)
        self.side = np.ones(model.num_particles)  # a sided shape: each particle's side
        self._sides_known = not shape.sided
        # this substep's contacts: how far the object pushed each particle, and along what
        self.depth = np.zeros(model.num_particles)
        self.normal_at = np.zeros((model.num_particles, 3))

    @property
    def friction(self) -> float:
        f = self._friction
        return f.value() if isinstance(f, FrictionSource) else f

    def center_at(self, t: float) -> np.ndarray:
        return self.center0 + orbit_offset(t) if self.moving else self.center0

    def sides(self, x: np.ndarray, center: np.ndarray) -> np.ndarray:
        """±1: the side of a sided shape each point is on."""
        return self.shape.sides(x - center, self.params[3:])

    def displacement(self, t: float, h: float) -> np.ndarray:
        """The object's motion over the substep [t, t + h], m."""
        return self.center_at(t + h) - self.center_at(t)

    def apply(self, state, h):
        before, after = self.center_at(state.t), self.center_at(state.t + h)
        self.center = after
        p = self.params
        p[0:3] = after
        if not self._sides_known:
            self.side[:] = self.sides(state.x_prev, before)  # before this substep
            self._sides_known = True
        collide_shape(state.x, self.inv_mass, self.side, self.shape.code, p, self.grid,
                      self.gradient, self.thickness, self.depth, self.normal_at)

    def apply_friction(self, state, h):
        d = self.displacement(state.t, h)
        apply_coulomb_friction(state.x, state.x_prev, self.depth, self.normal_at, d[0], d[1],
                               d[2], self.friction, KINETIC_SHARE * self.friction)

    def signed_distance(self, x: np.ndarray) -> np.ndarray:
        """Distance of each point outside the true surface (negative inside), m. A sided
        shape whose particles' sides are not known yet counts each point on its own side."""
        p = self.params.copy()
        p[0:3] = self.center
        side = self.side if self._sides_known else self.sides(x, self.center)
        out = np.empty(len(x))
        signed_distances(np.ascontiguousarray(x, dtype=np.float64), side, self.shape.code, p,
                         self.grid, self.gradient, out)
        return out

    def penetration(self, x: np.ndarray) -> float:
        """Deepest any free particle is inside the true surface, m."""
        free = self.inv_mass != 0.0
        if not free.any():
            return 0.0
        # signed_distance takes every particle: a plane's side is kept per particle
        return float(max(0.0, -self.signed_distance(x)[free].min()))

    def pose(self, t: float) -> ObjectPose | None:
        c = self.center_at(t)
        return ObjectPose(self.shape.name, self.parameters, tuple(float(v) for v in c))


class Floor(ShapeCollider):
    """The original's floor: the half-space below y = height, one-sided (anything below is
    pushed up). The renderer draws it from the scene, so it has no pose."""

    def __init__(self, model, height: float, friction: float | FrictionSource,
                 thickness: float):
        parameters = {"normal": (0.0, 1.0, 0.0)}
        inputs = plane.SHAPE.inputs_of(parameters)
        super().__init__(model, plane.SHAPE, inputs, (0.0, height, 0.0), friction=friction,
                         thickness=thickness)
        self.name = "collide_floor"
        self._sides_known = True  # every particle above: side[:] = +1

    def pose(self, t: float) -> ObjectPose | None:
        return None


def object_collider(model, obj, *, friction: float | FrictionSource, thickness: float,
                    where: str = "object") -> ShapeCollider:
    """The collider of one validated SceneObject (`where` names it in messages); its
    `friction` is a μs, or where the step's parameters hold it (read as it changes)."""
    shape = shape_of(obj.type)
    return ShapeCollider(model, shape, shape.kernel_inputs(obj, model.spacing, thickness, where),
                         obj.center, friction=friction, thickness=thickness,
                         moving=obj.motion == "orbit")


class ResolveContacts:
    """After the constraint pass: particles it pulled back inside an object are projected out
    again (adding to the contact's depth, the normal measure friction uses). Without this a
    sheet landing on the sphere at 4 substeps sinks 7–11 mm for a moment."""

    name = "resolve_contacts"

    def __init__(self, colliders: list[Collider]):
        self.colliders = colliders

    def apply(self, state, h):
        for collider in self.colliders:
            collider.apply(state, h)


class ContactFriction:
    """Coulomb friction of every collider's contacts of this substep, after the constraints
    (on the substep's whole motion, theirs included)."""

    name = "contact_friction"

    def __init__(self, colliders: list[Collider]):
        self.colliders = colliders

    def apply(self, state, h):
        for collider in self.colliders:
            collider.apply_friction(state, h)


class ContactsAfterFriction:
    """Friction moves a particle along one object's tangent, which can carry it into another
    object (in a crevice between two) or into a concave mesh: a last projection puts it out
    again (without it, 5 cm deep in a sphere wedged against a capsule). Those pushes only
    undo friction's own move, so they are not kept as depth for the next substep's
    friction."""

    name = "contacts_after_friction"

    def __init__(self, colliders: list[Collider]):
        self.colliders = colliders

    def apply(self, state, h):
        for collider in self.colliders:
            collider.apply(state, h)
            collider.depth.fill(0.0)


class ContactsAfterSoftPins(ContactsAfterFriction):
    """Soft pins pull after every other contact pass, so a target inside an object (a group
    held below the floor) would drag its particles in: at stiffness 0.999999, 9 m deep. One
    more projection after them makes contacts win over soft attachments; like the pass after
    friction it only undoes a move of this substep, so it keeps no depth for friction."""

    name = "contacts_after_soft_pins"


def orbit_offset(t: float) -> np.ndarray:
    """Displacement of a moving object at time t: a horizontal circle of ORBIT_RADIUS and
    ORBIT_PERIOD that passes through the object's own position at t = 0 (it starts where the
    scene puts it, moving along +x)."""
    a = 2.0 * math.pi * t / ORBIT_PERIOD
    return ORBIT_RADIUS * np.array([math.sin(a), 0.0, 1.0 - math.cos(a)])


def scene_objects(scene) -> list[tuple[str, object]]:
    """(key, SceneObject) of every object of the scene: scene.object (in the original's
    placement), then [[objects]] in order."""
    out = []
    if scene.scene.object != "none":
        shape = shape_of(scene.scene.object)
        out.append(("scene.object", SceneObject(type=shape.name, motion="orbit"
                                                if scene.scene.moving else "static",
                                                **shape.single_object)))
    out += [(f"objects[{k}]", o) for k, o in enumerate(scene.objects)]
    return out


def build_colliders(scene, model, params: StepParams | None = None) -> list[Collider]:
    """Collider effects the scene enables: the floor, then each object of scene_objects.
    With `params` each reads its friction from them as it runs (params.FrictionSource);
    without, it keeps the scene's numbers."""
    s = scene.scene
    out = []
    if s.floor:
        out.append(Floor(model, s.floor_height, _friction(s.friction, params), s.thickness))
    objects = scene_objects(scene)
    for shape in SHAPES.values():
        shape.check_scene([(where, o) for where, o in objects if o.type == shape.name])
    first = len(objects) - len(scene.objects)  # scene.object comes before [[objects]]
    out += [object_collider(model, o, where=where, thickness=s.thickness,
                            friction=_friction(s.friction if o.friction < 0 else o.friction,
                                               params, k - first))
            for k, (where, o) in enumerate(objects)]
    return out


def _friction(value: float, params: StepParams | None,
              index: int = -1) -> float | FrictionSource:
    """A collider's μs: `value`, or, with the step's `params`, where they hold it (the
    [[objects]] entry `index`, or the scene's for −1)."""
    return value if params is None else FrictionSource(params, max(index, -1))
