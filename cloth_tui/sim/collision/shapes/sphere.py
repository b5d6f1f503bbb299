"""A sphere of `radius` about its centre."""

from __future__ import annotations

import math

from ....object_shapes import SPHERE
from .base import AT_CENTRE, LENGTH, Shape


def distance(qx, qy, qz, p, side, grid, gradient):
    r = p[3]
    dist = math.sqrt(qx * qx + qy * qy + qz * qz)
    if dist < AT_CENTRE:  # at the centre: any direction is nearest; choose up
        return -r, 0.0, 1.0, 0.0
    return dist - r, qx / dist, qy / dist, qz / dist


class Sphere(Shape):
    name = "sphere"
    code = 0
    keys = SPHERE.keys
    parameter_kinds = {"radius": LENGTH}
    single_object = SPHERE.single_object
    distance = staticmethod(distance)

    def parameters(self, obj) -> dict:
        return {"radius": float(obj.radius)}

    def pack(self, parameters: dict) -> tuple:
        return (parameters["radius"],)

    def render_mesh(self, pv, parameters: dict):
        return pv.Sphere(radius=parameters["radius"], theta_resolution=40, phi_resolution=24)

    def define_usd(self, usd, stage, path: str, parameters: dict) -> None:
        usd.UsdGeom.Sphere.Define(stage, path).CreateRadiusAttr(parameters["radius"])


SHAPE = Sphere()
