"""A torus: a tube of `minor_radius` swept around a circle of `major_radius` about `axis`,
centred on the centre (a ring, a doughnut, a tyre).

For q relative to the centre, a the unit axis: t = q·a along the axis, e = q − t·a across
it, ρ = |e|. The nearest point of the tube's centre circle is R·ê, so w = (ρ − R)·ê + t·a
points from it to q, the distance is |w| − r and the normal ŵ. On the axis every point of
the circle is as near (any ê will do); on the centre circle itself ŵ has no direction and
the particle leaves outwards, along ê.
"""

from __future__ import annotations

import math

import numpy as np

from ....object_shapes import TORUS
from .base import AT_CENTRE, DIRECTION, LENGTH, Shape, unit

AROUND_RING = 64  # facets of the drawn surface around the axis
AROUND_TUBE = 24  # and around the tube


def distance(qx, qy, qz, p, side, grid, gradient):
    ax, ay, az, big, small = p[3], p[4], p[5], p[6], p[7]  # unit axis, R, r
    t = qx * ax + qy * ay + qz * az
    ex = qx - t * ax
    ey = qy - t * ay
    ez = qz - t * az
    rho = math.sqrt(ex * ex + ey * ey + ez * ez)
    if rho < AT_CENTRE:  # on the axis: every point of the circle is as near; choose one
        ex, ey, ez = (-ay, ax, 0.0) if abs(az) < 0.9 else (0.0, -az, ay)
        rho_e = math.sqrt(ex * ex + ey * ey + ez * ez)
        ex, ey, ez = ex / rho_e, ey / rho_e, ez / rho_e
    else:
        ex, ey, ez = ex / rho, ey / rho, ez / rho
    radial = rho - big
    wx = radial * ex + t * ax
    wy = radial * ey + t * ay
    wz = radial * ez + t * az
    w = math.sqrt(wx * wx + wy * wy + wz * wz)
    if w < AT_CENTRE:  # on the tube's centre circle: out along ê
        return -small, ex, ey, ez
    return w - small, wx / w, wy / w, wz / w


def surface(parameters: dict) -> tuple[np.ndarray, np.ndarray]:
    """(points, triangles) of the torus centred at the origin, every point on its surface:
    what the renderer draws and a bake's Mesh prim holds."""
    a = np.asarray(parameters["axis"], dtype=np.float64)
    u = np.cross(a, (1.0, 0.0, 0.0) if abs(a[0]) < 0.9 else (0.0, 1.0, 0.0))
    u /= np.linalg.norm(u)
    v = np.cross(a, u)
    big, small = parameters["major_radius"], parameters["minor_radius"]
    ring = np.linspace(0.0, 2.0 * np.pi, AROUND_RING, endpoint=False)
    tube = np.linspace(0.0, 2.0 * np.pi, AROUND_TUBE, endpoint=False)
    out = np.cos(ring)[:, None] * u + np.sin(ring)[:, None] * v  # ê around the ring
    radial = big + small * np.cos(tube)  # distance from the axis, per tube angle
    points = (radial[None, :, None] * out[:, None, :]
              + (small * np.sin(tube))[None, :, None] * a).reshape(-1, 3)
    i, j = np.meshgrid(np.arange(AROUND_RING), np.arange(AROUND_TUBE), indexing="ij")
    i1, j1 = (i + 1) % AROUND_RING, (j + 1) % AROUND_TUBE
    corner = lambda ii, jj: (ii * AROUND_TUBE + jj).ravel()  # noqa: E731
    quads = np.stack([corner(i, j), corner(i1, j), corner(i1, j1), corner(i, j1)], axis=1)
    triangles = np.concatenate([quads[:, [0, 1, 2]], quads[:, [0, 2, 3]]])
    return points, triangles


class Torus(Shape):
    name = "torus"
    code = 6
    keys = TORUS.keys
    parameter_kinds = {"axis": DIRECTION, "major_radius": LENGTH, "minor_radius": LENGTH}
    distance = staticmethod(distance)

    def parameters(self, obj) -> dict:
        return {"axis": unit(obj.axis), "major_radius": float(obj.major_radius),
                "minor_radius": float(obj.minor_radius)}

    def pack(self, parameters: dict) -> tuple:
        return (*parameters["axis"], parameters["major_radius"], parameters["minor_radius"])

    def render_mesh(self, pv, parameters: dict):
        points, triangles = surface(parameters)
        return pv.PolyData.from_regular_faces(points, triangles)

    def define_usd(self, usd, stage, path: str, parameters: dict) -> None:
        # usd-core has no torus schema prim: a Mesh of the drawn surface, the parameters
        # (written beside it) being what a bake reads back.
        UsdGeom, Vt = usd.UsdGeom, usd.Vt
        points, triangles = surface(parameters)
        shape = UsdGeom.Mesh.Define(stage, path)
        shape.CreatePointsAttr(Vt.Vec3fArray.FromNumpy(points.astype(np.float32)))
        shape.CreateFaceVertexCountsAttr(Vt.IntArray([3] * len(triangles)))
        shape.CreateFaceVertexIndicesAttr(Vt.IntArray(triangles.ravel().tolist()))
        shape.CreateSubdivisionSchemeAttr(UsdGeom.Tokens.none)


SHAPE = Torus()
