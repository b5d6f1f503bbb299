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

from .contact_kernels import (  # noqa: F401
    DISPATCHED,
    apply_coulomb_friction,
    collide_path,
    collide_shape,
    find_crossings,
    signed_distances,
)
from ..params import FrictionSource, StepParams
from ..protocols import Collider, ObjectPose
from .shapes import SHAPES, Shape, plane, shape_of
from .shapes.base import KernelInputs

ORBIT_RADIUS = 0.25   # m, radius of a moving object's horizontal circle
ORBIT_PERIOD = 10.0   # s, one revolution (≈ 0.16 m/s: the original's slow drift)
KINETIC_SHARE = 0.8   # μk / μs: sliding friction a little below sticking (typical of fabric)


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
        # each substep's path is checked for a crossing at the next one's first pass (its
        # start and time kept); a particle that went through is marked, with where it went
        # in and the normal there, until `penetration` measures how far beyond it still is
        self._start = np.zeros((model.num_particles, 3))
        self._start_t = math.nan
        self.crossed = np.zeros(model.num_particles, dtype=np.bool_)
        self.entry = np.zeros((model.num_particles, 3))
        self.entry_normal = np.zeros((model.num_particles, 3))

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
        if state.t != self._start_t:  # this substep's first pass
            self._check_last_substep(state, h, before)
        collide_path(state.x, state.x_prev, self.inv_mass, self.side, self.shape.code, p,
                     self.grid, self.gradient, self.thickness, self.depth, self.normal_at,
                     after - before)

    def _check_last_substep(self, state, h, before):
        """The path of the substep that ended where this one starts, if it did (not after a
        restored state), checked for a crossing; this one's start kept for the next."""
        # (a plane keeps each particle's side, which its distance measures)
        if self._start_t + h == state.t and not self.shape.sided:
            p = self.params.copy()
            p[0:3] = before
            find_crossings(self._start, state.x_prev, self.inv_mass, self.side,
                           self.shape.code, p, self.grid, self.gradient,
                           before - self.center_at(self._start_t), self.entry,
                           self.entry_normal, self.crossed)
        self._start[:] = state.x_prev
        self._start_t = state.t

    def sweep(self, state, start):
        if not self._sides_known:
            self.side[:] = self.sides(start, self.center_at(state.t))
            self._sides_known = True
        self.params[0:3] = self.center = self.center_at(state.t)
        scratch = np.zeros_like(self.depth)  # no contact of a substep: nothing for friction
        collide_path(state.x, start, self.inv_mass, self.side, self.shape.code, self.params,
                     self.grid, self.gradient, self.thickness, scratch, self.normal_at,
                     np.zeros(3))

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
        """Deepest any free particle is inside the true surface, or beyond it on the far side
        of the object it went through since the last measure (along the normal where it
        went in: a state restored to before it is not), m."""
        free = self.inv_mass != 0.0
        if not free.any():
            return 0.0
        # signed_distance takes every particle: a plane's side is kept per particle
        deepest = max(0.0, -self.signed_distance(x)[free].min())
        marked = self.crossed & free
        if marked.any():
            q = x[marked] - self.center - self.entry[marked]
            beyond = -np.einsum("ij,ij->i", q, self.entry_normal[marked])
            deepest = max(deepest, float(beyond.max()))
            self.crossed[:] = False
        return deepest

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
    placement), then [[objects]] in order (Scene.placed_objects)."""
    return scene.placed_objects()


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
