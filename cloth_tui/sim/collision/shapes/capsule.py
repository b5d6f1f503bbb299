"""A capsule: the points within `radius` of a segment of `length` along `axis` through the
centre (a cylinder of that length with hemispherical ends)."""

from __future__ import annotations

import math

from ....object_shapes import CAPSULE
from .base import AT_CENTRE, DIRECTION, LENGTH, Shape, turn_from_z, unit


def distance(qx, qy, qz, p, side, grid, gradient):
    ax, ay, az, half, r = p[3], p[4], p[5], p[6], p[7]  # unit axis, half length, radius
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


class Capsule(Shape):
    name = "capsule"
    code = 2
    keys = CAPSULE.keys
    parameter_kinds = {"radius": LENGTH, "axis": DIRECTION, "length": LENGTH}
    single_object = CAPSULE.single_object
    distance = staticmethod(distance)

    def parameters(self, obj) -> dict:
        return {"radius": float(obj.radius), "axis": unit(obj.axis),
                "length": float(obj.length)}

    def pack(self, parameters: dict) -> tuple:
        return (*parameters["axis"], 0.5 * parameters["length"], parameters["radius"])

    def render_mesh(self, pv, parameters: dict):
        return pv.Capsule(direction=parameters["axis"], radius=parameters["radius"],
                          cylinder_length=parameters["length"], resolution=30).triangulate()

    def define_usd(self, usd, stage, path: str, parameters: dict) -> None:
        UsdGeom = usd.UsdGeom
        shape = UsdGeom.Capsule.Define(stage, path)
        shape.CreateAxisAttr(UsdGeom.Tokens.z)
        shape.CreateRadiusAttr(parameters["radius"])
        shape.CreateHeightAttr(parameters["length"])
        shape.AddOrientOp(UsdGeom.XformOp.PrecisionFloat).Set(
            turn_from_z(usd, parameters["axis"]))


SHAPE = Capsule()
