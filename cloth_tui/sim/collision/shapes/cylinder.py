"""A capped cylinder: a disc of `radius` about `axis`, swept `height` along it, centred on
the centre (flat ends, sharp rims).

For q relative to the centre, a the unit axis: t = q·a along the axis, e = q − t·a across
it, ρ = |e|. The rim's two distances are dr = ρ − radius (to the side) and dh = |t| − h/2
(to an end). Outside (dr > 0 or dh > 0) the distance is |(max(dr, 0), max(dh, 0))|, the
normal the same blend of ê = e/ρ and sign(t)·a (a corner rounds off, as the box's do);
inside it is max(dr, dh), leaving through the nearer of the side and the end.
"""

from __future__ import annotations

import math

from ....object_shapes import CYLINDER
from .base import AT_CENTRE, DIRECTION, LENGTH, Shape, turn_from_z, unit

SIDES_DRAWN = 48  # facets around the rendered side


def distance(qx, qy, qz, p, side, grid, gradient):
    ax, ay, az, half, r = p[3], p[4], p[5], p[6], p[7]  # unit axis, half height, radius
    t = qx * ax + qy * ay + qz * az
    ex = qx - t * ax
    ey = qy - t * ay
    ez = qz - t * az
    rho = math.sqrt(ex * ex + ey * ey + ez * ez)
    if rho < AT_CENTRE:  # on the axis: any direction across it is the side's; choose one
        ex, ey, ez = (-ay, ax, 0.0) if abs(az) < 0.9 else (0.0, -az, ay)
        rho_e = math.sqrt(ex * ex + ey * ey + ez * ez)
        ex, ey, ez = ex / rho_e, ey / rho_e, ez / rho_e
    else:
        ex, ey, ez = ex / rho, ey / rho, ez / rho
    s = 1.0 if t >= 0.0 else -1.0
    dr = rho - r
    dh = abs(t) - half
    if dr > 0.0 or dh > 0.0:
        wr = max(dr, 0.0)
        wh = max(dh, 0.0)
        d = math.sqrt(wr * wr + wh * wh)
        wr, wh = wr / d, s * wh / d
        return d, wr * ex + wh * ax, wr * ey + wh * ay, wr * ez + wh * az
    if dr > dh:  # inside: out through the side
        return dr, ex, ey, ez
    return dh, s * ax, s * ay, s * az


class Cylinder(Shape):
    name = "cylinder"
    code = 5
    keys = CYLINDER.keys
    parameter_kinds = {"radius": LENGTH, "axis": DIRECTION, "height": LENGTH}
    distance = staticmethod(distance)

    def parameters(self, obj) -> dict:
        return {"radius": float(obj.radius), "axis": unit(obj.axis),
                "height": float(obj.height)}

    def pack(self, parameters: dict) -> tuple:
        return (*parameters["axis"], 0.5 * parameters["height"], parameters["radius"])

    def render_mesh(self, pv, parameters: dict):
        return pv.Cylinder(center=(0.0, 0.0, 0.0), direction=parameters["axis"],
                           radius=parameters["radius"], height=parameters["height"],
                           resolution=SIDES_DRAWN, capping=True).triangulate()

    def define_usd(self, usd, stage, path: str, parameters: dict) -> None:
        UsdGeom = usd.UsdGeom
        shape = UsdGeom.Cylinder.Define(stage, path)
        shape.CreateAxisAttr(UsdGeom.Tokens.z)
        shape.CreateRadiusAttr(parameters["radius"])
        shape.CreateHeightAttr(parameters["height"])
        shape.AddOrientOp(UsdGeom.XformOp.PrecisionFloat).Set(
            turn_from_z(usd, parameters["axis"]))


SHAPE = Cylinder()
