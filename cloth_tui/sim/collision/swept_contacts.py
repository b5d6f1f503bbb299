"""Continuous collision of particles against one object: a particle whose substep path crosses
the surface is stopped on the side it came from (conservative advancement, after Bridson,
Fedkiw & Anderson 2002 and Provot 1997: process the motion, not only where it ends).

A shape's signed distance d is 1-Lipschitz (an exact distance; a mesh's trilinear grid
nearly so, hence SAFETY), so a point at distance d can move d in any direction without
reaching the surface. Sphere tracing walks the straight path of a substep, x_prev → x in the
object's frame, in steps of (d − level)·SAFETY: it never passes below `level` and stops
within a band above it, the path's first approach.

The level (level_of) is half the skin for a particle that starts outside the skin, half its
start's distance for one in the skin (a resting particle slides along it but cannot sink
through), and its start for one already inside. At an approach the rest of the motion loses
its part into the surface (the contact's response, kept as depth for friction) and is walked
again from there, up to PASSES times; a particle still approaching then stays where it was
stopped. Any point above such a level is on its own side, and the projection
(contact_kernels.push_out_of_contact) takes it out to the skin.

Only a path that may come below its level is walked: an end farther than the path's length
plus half the skin, or a start farther than the length above its level, proves it cannot,
which is every particle away from the object or resting on it. A plane needs no walk: each
particle keeps its side, which the projection restores from any depth.
"""

from __future__ import annotations

import math

from ..jit import kernel
from .shapes import box, capsule, cylinder, mesh, plane, sphere, torus
from .shapes.mesh import OUTSIDE

SAFETY = 0.9      # share of the distance stepped (a mesh grid is nearly 1-Lipschitz)
STOP = 1e-6       # m: this close to the level is an approach, and a tenth of the skin closer
BAND_SHARE = 0.1  # (a path grazing the level would otherwise crawl along it in tiny steps)
MAX_STEPS = 64    # a walk still short of its end after these stops there (a long graze)
PASSES = 3        # approaches answered in one substep's path before the particle stops
BELOW = 1e-5      # m: how far below its level a path may go (a surface without a skin)
BEYOND_GRID = 0.5 * OUTSIDE  # a mesh distance this large is "outside the grid"
THROUGH = 1e-4    # m inside the surface: a path this deep went into the object
LONGEST_PATH = 1e3  # m: a substep path longer than this is a diverging step's, not checked
GRAZE_RESUMES = 64  # walks of MAX_STEPS a crossing check may take along one path


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


@kernel()
def distance_at(code, qx, qy, qz, p, side, grid, gradient):
    """The distance of shape `code` at q, branching on each call: the walk is the rare path,
    compiled once for every shape (contact_kernels.for_shape's per-shape loops are the common
    one)."""
    if code == SPHERE:
        return _sphere(qx, qy, qz, p, side, grid, gradient)
    if code == BOX:
        return _box(qx, qy, qz, p, side, grid, gradient)
    if code == CAPSULE:
        return _capsule(qx, qy, qz, p, side, grid, gradient)
    if code == PLANE:
        return _plane(qx, qy, qz, p, side, grid, gradient)
    if code == MESH:
        return _mesh(qx, qy, qz, p, side, grid, gradient)
    if code == CYLINDER:
        return _cylinder(qx, qy, qz, p, side, grid, gradient)
    if code == TORUS:
        return _torus(qx, qy, qz, p, side, grid, gradient)
    return math.nan, 0.0, 1.0, 0.0


@kernel(inline="always")
def level_of(d_start, thickness):
    """How near the surface a path that starts `d_start` from it may come: half the skin, or
    half its start within the skin, or no deeper than its start inside the object. Any point
    above a level ≥ −BELOW is on its own side, where the projection takes it out."""
    if d_start >= 0.0:
        return 0.5 * min(d_start, thickness) - BELOW
    return d_start - BELOW


@kernel()
def grid_entry(sx, sy, sz, vx, vy, vz, t, p, grid):
    """The path parameter (≥ t) at which s + t·v enters a mesh's distance grid (p[3:6] its
    corner, p[6] 1/cell), or 2.0 if it does not before t = 1."""
    lo_t = t
    hi_t = 1.0
    for axis in range(3):
        s = (sx, sy, sz)[axis]
        v = (vx, vy, vz)[axis]
        lo = p[3 + axis]
        hi = lo + (grid.shape[axis] - 1) / p[6]
        if v == 0.0:
            if s < lo or s > hi:
                return 2.0
            continue
        a = (lo - s) / v
        b = (hi - s) / v
        if a > b:
            a, b = b, a
        lo_t = max(lo_t, a)
        hi_t = min(hi_t, b)
    return lo_t if lo_t <= hi_t else 2.0


@kernel()
def first_approach(code, p, side, grid, gradient, sx, sy, sz, ex, ey, ez, level, band):
    """(t, d, nx, ny, nz) at the first point of the path s → e (object frame) that comes
    within `band` of `level`, t in [0, 1]; t = 2.0 if none does."""
    vx = ex - sx
    vy = ey - sy
    vz = ez - sz
    length = math.sqrt(vx * vx + vy * vy + vz * vz)
    t = 0.0
    for _ in range(MAX_STEPS):
        d, nx, ny, nz = distance_at(code, sx + t * vx, sy + t * vy, sz + t * vz, p, side,
                                    grid, gradient)
        if code == MESH and d >= BEYOND_GRID:  # no distance outside the grid: walk to its edge
            entry = grid_entry(sx, sy, sz, vx, vy, vz, t, p, grid)
            if entry > 1.0:
                return 2.0, d, nx, ny, nz
            t = entry + STOP / max(length, STOP)
            continue
        gap = d - level
        if gap < band:
            return t, d, nx, ny, nz
        if length == 0.0:
            return 2.0, d, nx, ny, nz
        t += SAFETY * gap / length
        if t > 1.0:
            return 2.0, d, nx, ny, nz
    return t, d, nx, ny, nz  # a long graze: stop where the walk got


@kernel()
def walk_path(code, p, side, grid, gradient, sx, sy, sz, ex, ey, ez, d_start, thickness):
    """Where a particle moving s → e ends (object frame) when stopped on its side of the
    surface: (x, y, z, pushed, nx, ny, nz), `pushed` the motion into the surface it lost
    (0 with no approach) and n the normal of the last approach."""
    level = level_of(d_start, thickness)
    band = STOP + BAND_SHARE * thickness
    pushed = nx = ny = nz = 0.0
    for k in range(PASSES):
        t, d, hx, hy, hz = first_approach(code, p, side, grid, gradient, sx, sy, sz, ex, ey,
                                          ez, level, band)
        if t > 1.0:
            break
        ax = sx + t * (ex - sx)
        ay = sy + t * (ey - sy)
        az = sz + t * (ez - sz)
        rx = ex - ax
        ry = ey - ay
        rz = ez - az
        rn = rx * hx + ry * hy + rz * hz
        nx, ny, nz = hx, hy, hz
        if k == PASSES - 1:  # still approaching: it stays where it was stopped
            pushed += max(-rn, 0.0)
            ex, ey, ez = ax, ay, az
            break
        if rn < 0.0:  # the rest of the motion without its part into the surface
            rx -= rn * hx
            ry -= rn * hy
            rz -= rn * hz
            pushed -= rn
        sx, sy, sz = ax, ay, az
        ex, ey, ez = ax + rx, ay + ry, az + rz
        level = level_of(d, thickness)
    return ex, ey, ez, pushed, nx, ny, nz


@kernel(inline="always")
def may_cross(d_end, length2, thickness):
    """Whether a path of squared length `length2` ending `d_end` from the surface may have
    come below its level (at most half the skin): the cheap test, before the start's
    distance is known, without a square root."""
    clear = d_end - 0.5 * thickness
    return clear <= 0.0 or clear * clear < length2


@kernel()
def crossed_by(code, p, side, grid, gradient, sx, sy, sz, ex, ey, ez, d_end):
    """(t, n) where a path s → e (object frame) from outside the object went into it, with
    the outward normal there, if it went through to end outside again; t = 2.0 if not (a
    path that starts or ends inside is measured by the distance there)."""
    if d_end < 0.0:
        return 2.0, 0.0, 1.0, 0.0
    d_start, _, _, _ = distance_at(code, sx, sy, sz, p, side, grid, gradient)
    if d_start < 0.0:
        return 2.0, 0.0, 1.0, 0.0
    # A walk that ran out of steps along a graze (a particle sliding along the skin) is
    # resumed from where it got: only a point that came within STOP of the level went in.
    t = 0.0
    for _ in range(GRAZE_RESUMES):
        ax = sx + t * (ex - sx)
        ay = sy + t * (ey - sy)
        az = sz + t * (ez - sz)
        u, d, nx, ny, nz = first_approach(code, p, side, grid, gradient, ax, ay, az, ex, ey,
                                          ez, -THROUGH, STOP)
        if u > 1.0:
            return 2.0, 0.0, 1.0, 0.0
        t += u * (1.0 - t)
        if d + THROUGH < STOP:
            return t, nx, ny, nz
    return 2.0, 0.0, 1.0, 0.0  # a graze longer than the resumes: it never went in
