"""An axis-aligned box of sides `size` about its centre."""

from __future__ import annotations

import math

from ....object_shapes import BOX
from .base import SIDES, Shape


def distance(qx, qy, qz, p, side, grid, gradient):
    ox = abs(qx) - p[3]  # p[3:6]: the half sides
    oy = abs(qy) - p[4]
    oz = abs(qz) - p[5]
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


class Box(Shape):
    name = "box"
    code = 1
    keys = BOX.keys
    parameter_kinds = {"size": SIDES}
    single_object = BOX.single_object
    smooth = False
    distance = staticmethod(distance)

    def parameters(self, obj) -> dict:
        return {"size": tuple(float(v) for v in obj.size)}

    def pack(self, parameters: dict) -> tuple:
        return tuple(0.5 * v for v in parameters["size"])

    def render_mesh(self, pv, parameters: dict):
        sx, sy, sz = (v / 2 for v in parameters["size"])
        return pv.Box((-sx, sx, -sy, sy, -sz, sz))

    def define_usd(self, usd, stage, path: str, parameters: dict) -> None:
        cube = usd.UsdGeom.Cube.Define(stage, path)
        cube.CreateSizeAttr(1.0)
        cube.AddScaleOp().Set(usd.Gf.Vec3f(*parameters["size"]))


SHAPE = Box()
