"""A capsule: the points within `radius` of a segment of `length` along `axis` through the
centre (a cylinder of that length with hemispherical ends)."""

from __future__ import annotations

import math

from ....scene_keys import SceneError, key
from . import box, plane
from .base import (AT_CENTRE, AXIS_KEY, DIRECTION, LENGTH, RADIUS_KEY, Shape, default_of,
                   turn_from_z, unit)


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
    keys = {"radius": RADIUS_KEY, "axis": AXIS_KEY,
            "length": key(0.5, "length of the axis segment (the capsule's cylinder part)",
                          unit="m", lo=0.0, hi=1e3)}
    parameter_kinds = {"radius": LENGTH, "axis": DIRECTION, "length": LENGTH}
    # the original's: lying along x under the sheet's centre
    single_object = dict(center=[0.0, -0.1, 0.0], radius=0.15, length=0.5,
                         axis=[1.0, 0.0, 0.0])
    distance = staticmethod(distance)

    def check(self, obj, where: str) -> None:
        if (obj.normal != default_of(plane.SHAPE.keys["normal"])
                or obj.size != default_of(box.SHAPE.keys["size"])):
            raise SceneError(f"{where}: a capsule takes `axis` (direction) and `length` "
                             "(m), not `normal` and `size` (older files put the axis in normal "
                             "and the length in size[1]); move them to axis and length")

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
