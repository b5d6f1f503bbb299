"""The compiled contact kernels of sim/colliders.py: each shape's distance through one
dispatch (for_shape), the contact along a substep's path (swept_contacts) and the projection,
Coulomb friction, the distance measure and the crossing check."""

from __future__ import annotations

import math

import numpy as np

from . import swept_contacts
from ..jit import kernel
from .shapes import box, capsule, cylinder, mesh, plane, sphere, torus

# ---------------------------------------------------------------------------------------
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
    x, x_prev, inv_mass, side, p, grid, gradient, thickness, depth, normal, moved, code, \
        swept = args
    cx, cy, cz = p[0], p[1], p[2]
    for i in range(x.shape[0]):
        if inv_mass[i] == 0.0:
            continue
        qx = x[i, 0] - cx
        qy = x[i, 1] - cy
        qz = x[i, 2] - cz
        d, nx, ny, nz = distance(qx, qy, qz, p, side[i], grid, gradient)
        if swept:  # the substep's path, from where it started relative to the object then
            sx = x_prev[i, 0] - cx + moved[0]
            sy = x_prev[i, 1] - cy + moved[1]
            sz = x_prev[i, 2] - cz + moved[2]
            length2 = (qx - sx) ** 2 + (qy - sy) ** 2 + (qz - sz) ** 2
            if swept_contacts.may_cross(d, length2, thickness):
                length = math.sqrt(length2)
                d0, _, _, _ = swept_contacts.distance_at(code, sx, sy, sz, p, side[i], grid,
                                                         gradient)
                if d0 - length < swept_contacts.level_of(d0, thickness):
                    ex, ey, ez, pushed, hx, hy, hz = swept_contacts.walk_path(
                        code, p, side[i], grid, gradient, sx, sy, sz, qx, qy, qz, d0,
                        thickness)
                    if pushed > 0.0:
                        depth[i] += pushed
                        normal[i, 0] = hx
                        normal[i, 1] = hy
                        normal[i, 2] = hz
                    if ex != qx or ey != qy or ez != qz:
                        x[i, 0] = ex + cx
                        x[i, 1] = ey + cy
                        x[i, 2] = ez + cz
                        d, nx, ny, nz = swept_contacts.distance_at(code, ex, ey, ez, p,
                                                                   side[i], grid, gradient)
        if d < thickness:
            push_out_of_contact(x, i, d, nx, ny, nz, thickness, depth, normal)


@kernel()
def collide_path(x, x_prev, inv_mass, side, code, p, grid, gradient, thickness, depth,
                 normal, moved):
    """Contact for one object: a particle whose substep path x_prev → x comes into the skin
    is stopped on the side it came from (swept_contacts; `moved` is the object's own
    displacement this substep), then a particle inside the skin goes out along the normal to
    the skin's surface; depth[i] += how far, normal[i] = n. side[i] = ±1 is the side of a
    plane the particle started on (an infinite plane cannot be walked around, so it keeps it,
    and needs no path); other shapes ignore it."""
    for_shape(code, _contacts, (x, x_prev, inv_mass, side, p, grid, gradient, thickness,
                                depth, normal, moved, code, code != PLANE))


@kernel()
def collide_shape(x, inv_mass, side, code, p, grid, gradient, thickness, depth, normal):
    """The projection alone (collide_path for points that did not move)."""
    for_shape(code, _contacts, (x, x, inv_mass, side, p, grid, gradient, thickness, depth,
                                normal, np.zeros(3), code, False))


@kernel(inline="always")
def _crossings(distance, args):
    start, end, inv_mass, side, p, grid, gradient, moved, code, entry, entry_normal, \
        crossed = args
    cx, cy, cz = p[0], p[1], p[2]
    for i in range(end.shape[0]):
        if inv_mass[i] == 0.0:
            continue
        ex = end[i, 0] - cx
        ey = end[i, 1] - cy
        ez = end[i, 2] - cz
        d, _, _, _ = distance(ex, ey, ez, p, side[i], grid, gradient)
        sx = start[i, 0] - cx + moved[0]
        sy = start[i, 1] - cy + moved[1]
        sz = start[i, 2] - cz + moved[2]
        length = math.sqrt((ex - sx) ** 2 + (ey - sy) ** 2 + (ez - sz) ** 2)
        if d - length >= 0.0 or not length < swept_contacts.LONGEST_PATH:
            continue  # every point of the path is outside, or it is a diverged step's
        t, nx, ny, nz = swept_contacts.crossed_by(code, p, side[i], grid, gradient, sx, sy, sz,
                                                  ex, ey, ez, d)
        if t <= 1.0:
            entry[i, 0] = sx + t * (ex - sx)
            entry[i, 1] = sy + t * (ey - sy)
            entry[i, 2] = sz + t * (ez - sz)
            entry_normal[i, 0] = nx
            entry_normal[i, 1] = ny
            entry_normal[i, 2] = nz
            crossed[i] = True


@kernel()
def find_crossings(start, end, inv_mass, side, code, p, grid, gradient, moved, entry,
                   entry_normal, crossed):
    """A particle whose substep path start → end (`moved` the object's displacement over it,
    p its centre at the end) went through the object to its far side, which the contacts let
    pass: crossed[i], with where it went in (object frame) and the outward normal there. A
    path sliding along the skin, however long, did not go in."""
    for_shape(code, _crossings, (start, end, inv_mass, side, p, grid, gradient, moved, code,
                                 entry, entry_normal, crossed))


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


