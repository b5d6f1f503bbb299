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

from .jit import kernel
from .protocols import Collider, ObjectPose

ORBIT_RADIUS = 0.25   # m, radius of a moving object's horizontal circle
ORBIT_PERIOD = 10.0   # s, one revolution (≈ 0.16 m/s: the original's slow drift)
PLANE_TILT_DEG = 20.0  # the single `scene.object = "plane"` is tilted this much about x
AT_CENTRE = 1e-12     # m: a point this close to a centre or axis has no normal of its own
KINETIC_SHARE = 0.8   # μk / μs: sliding friction a little below sticking (typical of fabric)


# -- kernels --------------------------------------------------------------------------------
# Each shape has a distance function (signed distance d of a point q given relative to the
# shape's centre, and the outward unit normal there), written once: the contact kernel and
# the penetration measure both call it through _shape_distance.
@kernel(inline="always")
def _sphere_distance(qx, qy, qz, r):
    dist = math.sqrt(qx * qx + qy * qy + qz * qz)
    if dist < AT_CENTRE:  # at the centre: any direction is nearest; choose up
        return -r, 0.0, 1.0, 0.0
    return dist - r, qx / dist, qy / dist, qz / dist


@kernel(inline="always")
def _box_distance(qx, qy, qz, hx, hy, hz):
    """Axis-aligned box of half sides h."""
    ox = abs(qx) - hx
    oy = abs(qy) - hy
    oz = abs(qz) - hz
    sx = 1.0 if qx >= 0.0 else -1.0
    sy = 1.0 if qy >= 0.0 else -1.0
    sz = 1.0 if qz >= 0.0 else -1.0
    if ox > 0.0 or oy > 0.0 or oz > 0.0:
        ux = sx * max(ox, 0.0)
        uy = sy * max(oy, 0.0)
        uz = sz * max(oz, 0.0)
        d = math.sqrt(ux * ux + uy * uy + uz * uz)
        return d, ux / d, uy / d, uz / d
    if ox >= oy and ox >= oz:  # inside: leave through the nearest face
        return ox, sx, 0.0, 0.0
    if oy >= oz:
        return oy, 0.0, sy, 0.0
    return oz, 0.0, 0.0, sz


@kernel(inline="always")
def _capsule_distance(qx, qy, qz, ax, ay, az, half, r):
    """Points within r of the segment ±half·a (a unit) through the centre."""
    t = min(max(qx * ax + qy * ay + qz * az, -half), half)
    ex = qx - t * ax
    ey = qy - t * ay
    ez = qz - t * az
    dist = math.sqrt(ex * ex + ey * ey + ez * ez)
    if dist < AT_CENTRE:  # on the axis: leave perpendicular to it
        ex, ey, ez = (-ay, ax, 0.0) if abs(az) < 0.9 else (0.0, -az, ay)
        dist = math.sqrt(ex * ex + ey * ey + ez * ez)
        return -r, ex / dist, ey / dist, ez / dist
    return dist - r, ex / dist, ey / dist, ez / dist


@kernel(inline="always")
def _plane_distance(qx, qy, qz, nx, ny, nz):
    d = qx * nx + qy * ny + qz * nz
    return d, nx, ny, nz


SPHERE, BOX, CAPSULE, PLANE = 0, 1, 2, 3
SHAPES = {"sphere": SPHERE, "box": BOX, "capsule": CAPSULE, "plane": PLANE}


@kernel(inline="always")
def _shape_distance(shape, qx, qy, qz, p, s):
    """Signed distance and outward normal of `shape` with parameters p (p[0:3] the centre, then
    sphere: r; box: half sides; capsule: axis, half length, r; plane: normal), for a point q
    relative to the centre. s = ±1 picks the side of a two-sided plane."""
    if shape == SPHERE:
        return _sphere_distance(qx, qy, qz, p[3])
    if shape == BOX:
        return _box_distance(qx, qy, qz, p[3], p[4], p[5])
    if shape == CAPSULE:
        return _capsule_distance(qx, qy, qz, p[3], p[4], p[5], p[6], p[7])
    return _plane_distance(qx, qy, qz, s * p[3], s * p[4], s * p[5])


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


@kernel()
def collide_shape(x, inv_mass, side, shape, p, thickness, depth, normal):
    """Contact projection for one object: a particle inside the skin goes out along the
    normal to the skin's surface; depth[i] += how far, normal[i] = n. side[i] = ±1 is the
    side of a plane the particle started on (an infinite plane cannot be walked around, so
    it keeps it); other shapes ignore it."""
    cx, cy, cz = p[0], p[1], p[2]
    for i in range(x.shape[0]):
        if inv_mass[i] == 0.0:
            continue
        d, nx, ny, nz = _shape_distance(shape, x[i, 0] - cx, x[i, 1] - cy, x[i, 2] - cz, p,
                                        side[i])
        if d < thickness:
            push_out_of_contact(x, i, d, nx, ny, nz, thickness, depth, normal)


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


@kernel()
def signed_distances(x, side, shape, p, out):
    """out[i] = signed distance of point i from the true surface (negative inside), m: the
    same distance function the contact kernel uses."""
    cx, cy, cz = p[0], p[1], p[2]
    for i in range(x.shape[0]):
        d, _, _, _ = _shape_distance(shape, x[i, 0] - cx, x[i, 1] - cy, x[i, 2] - cz, p, side[i])
        out[i] = d


# -- effects --------------------------------------------------------------------------------
class ShapeCollider:
    """One static shape, described by its kernel code and parameters (see _shape_distance)."""

    moving = False

    def __init__(self, model, name: str, shape: int, center, friction: float,
                 thickness: float):
        self.name = name
        self.shape = shape
        self.inv_mass = model.inv_mass
        self.center0 = np.asarray(center, dtype=np.float64)
        self.center = self.center0.copy()
        self.params = np.zeros(8)  # centre, then the shape's own (see _shape_distance)
        self.friction, self.thickness = float(friction), float(thickness)
        self.side = np.ones(model.num_particles)  # plane: side of each particle
        self._sides_known = shape != PLANE
        # this substep's contacts: how far the object pushed each particle, and along what
        self.depth = np.zeros(model.num_particles)
        self.normal_at = np.zeros((model.num_particles, 3))

    def center_at(self, t: float) -> np.ndarray:
        return self.center0

    def _sides(self, x: np.ndarray, center: np.ndarray) -> np.ndarray:
        """±1: the side of a plane each point is on."""
        return np.where((x - center) @ self.params[3:6] >= 0.0, 1.0, -1.0)

    def displacement(self, t: float, h: float) -> np.ndarray:
        """The object's motion over the substep [t, t + h], m."""
        return self.center_at(t + h) - self.center_at(t)

    def apply(self, state, h):
        before, after = self.center_at(state.t), self.center_at(state.t + h)
        self.center = after
        p = self.params
        p[0:3] = after
        if not self._sides_known:
            self.side[:] = self._sides(state.x_prev, before)  # before this substep
            self._sides_known = True
        collide_shape(state.x, self.inv_mass, self.side, self.shape, p, self.thickness,
                      self.depth, self.normal_at)

    def apply_friction(self, state, h):
        d = self.displacement(state.t, h)
        apply_coulomb_friction(state.x, state.x_prev, self.depth, self.normal_at, d[0], d[1],
                               d[2], self.friction, KINETIC_SHARE * self.friction)

    def signed_distance(self, x: np.ndarray) -> np.ndarray:
        """Distance of each point outside the true surface (negative inside), m. A plane
        whose particles' sides are not known yet counts each point on its own side."""
        p = self.params.copy()
        p[0:3] = self.center
        side = self.side if self._sides_known else self._sides(x, self.center)
        out = np.empty(len(x))
        signed_distances(np.ascontiguousarray(x, dtype=np.float64), side, self.shape, p, out)
        return out

    def penetration(self, x: np.ndarray) -> float:
        """Deepest any free particle is inside the true surface, m."""
        free = self.inv_mass != 0.0
        if not free.any():
            return 0.0
        # signed_distance takes every particle: a plane's side is kept per particle
        return float(max(0.0, -self.signed_distance(x)[free].min()))

    def pose(self, t: float) -> ObjectPose | None:
        return None


class Floor(ShapeCollider):
    """The original's floor: the half-space below y = height, one-sided (anything below is
    pushed up). The renderer draws it from the scene, so it has no pose."""

    def __init__(self, model, height: float, friction: float, thickness: float):
        super().__init__(model, "collide_floor", PLANE, (0.0, height, 0.0), friction,
                         thickness)
        self.params[3:6] = 0.0, 1.0, 0.0
        self._sides_known = True  # every particle above: side[:] = +1


class ObjectCollider(ShapeCollider):
    """A sphere, box, plane or capsule; static, or moving along the orbit."""

    def __init__(self, model, kind: str, center, *, radius=0.25, size=(0.5, 0.2, 0.5),
                 normal=(0.0, 1.0, 0.0), axis=(1.0, 0.0, 0.0), length=0.5, friction=0.9,
                 thickness=0.005, moving=False):
        super().__init__(model, f"collide_{kind}", SHAPES[kind], center, friction, thickness)
        self.kind, self.moving = kind, moving
        self.radius = float(radius)
        self.size = np.asarray(size, dtype=np.float64)
        self.normal = _unit(normal)
        self.axis = _unit(axis)
        self.length = float(length)
        if kind == "sphere":
            self.params[3] = self.radius
        elif kind == "box":
            self.params[3:6] = 0.5 * self.size
        elif kind == "capsule":
            self.params[3:6] = self.axis
            self.params[6:8] = 0.5 * self.length, self.radius
        else:
            self.params[3:6] = self.normal

    def center_at(self, t: float) -> np.ndarray:
        return self.center0 + orbit_offset(t) if self.moving else self.center0

    def pose(self, t: float) -> ObjectPose:
        c = self.center_at(t)
        return ObjectPose(self.kind, tuple(float(v) for v in c), self.radius,
                          tuple(float(v) for v in self.size),
                          tuple(float(v) for v in self.normal),
                          tuple(float(v) for v in self.axis), self.length)


def _unit(v) -> np.ndarray:
    v = np.asarray(v, dtype=np.float64)
    return v / np.linalg.norm(v)


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
    """Coulomb friction of every collider's contacts of this substep, after the constraints.
    Friction moves a particle along one object's tangent, which can carry it into another
    object (in a crevice between two) or into a concave mesh: a last projection puts it out
    again (without it, 5 cm deep in a sphere wedged against a capsule). Those pushes only
    undo friction's own move, so the next substep's friction does not count them."""

    name = "contact_friction"

    def __init__(self, colliders: list[Collider]):
        self.colliders = colliders

    def apply(self, state, h):
        for collider in self.colliders:
            collider.apply_friction(state, h)
        for collider in self.colliders:
            collider.apply(state, h)
            collider.depth.fill(0.0)


def orbit_offset(t: float) -> np.ndarray:
    """Displacement of a moving object at time t: a horizontal circle of ORBIT_RADIUS and
    ORBIT_PERIOD that passes through the object's own position at t = 0 (it starts where the
    scene puts it, moving along +x)."""
    a = 2.0 * math.pi * t / ORBIT_PERIOD
    return ORBIT_RADIUS * np.array([math.sin(a), 0.0, 1.0 - math.cos(a)])


def single_object(kind: str) -> dict:
    """The original's single object in SI units (its 500-unit sheet → 1 m): sphere r 0.25
    resting on the floor (−0.5); box 0.5×0.2×0.5 at the origin; a plane through the origin
    tilted 20° about x; a capsule lying along x under the sheet's centre."""
    tilt = math.radians(PLANE_TILT_DEG)
    return {
        "sphere": dict(center=(0.0, -0.25, 0.0), radius=0.25),
        "box": dict(center=(0.0, 0.0, 0.0), size=(0.5, 0.2, 0.5)),
        "plane": dict(center=(0.0, 0.0, 0.0), normal=(0.0, math.cos(tilt), math.sin(tilt))),
        "capsule": dict(center=(0.0, -0.1, 0.0), radius=0.15, length=0.5,
                        axis=(1.0, 0.0, 0.0)),
    }[kind]


def build_colliders(scene, model) -> list[Collider]:
    """Collider effects the scene enables: the floor, then scene.object, then [[objects]]
    (meshes apart: mesh_collider.build_mesh_colliders)."""
    s = scene.scene
    out = []
    if s.floor:
        out.append(Floor(model, s.floor_height, s.friction, s.thickness))
    if s.object != "none":
        out.append(ObjectCollider(model, s.object, friction=s.friction, thickness=s.thickness,
                                  moving=s.moving, **single_object(s.object)))
    for o in scene.objects:
        if o.type == "mesh":
            continue
        out.append(ObjectCollider(model, o.type, o.center, radius=o.radius, size=o.size,
                                  normal=o.normal, axis=o.axis, length=o.length,
                                  thickness=s.thickness,
                                  friction=s.friction if o.friction < 0 else o.friction,
                                  moving=o.motion == "orbit"))
    return out
