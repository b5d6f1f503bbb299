"""A sphere of `radius` about its centre."""

from __future__ import annotations

import math

from .base import AT_CENTRE, LENGTH, RADIUS_KEY, Shape


def distance(qx, qy, qz, p, side, grid, gradient):
    r = p[3]
    dist = math.sqrt(qx * qx + qy * qy + qz * qz)
    if dist < AT_CENTRE:  # at the centre: any direction is nearest; choose up
        return -r, 0.0, 1.0, 0.0
    return dist - r, qx / dist, qy / dist, qz / dist


class Sphere(Shape):
    name = "sphere"
    code = 0
    keys = {"radius": RADIUS_KEY}
    parameter_kinds = {"radius": LENGTH}
    # the original's: radius 0.25 resting on the floor (−0.5)
    single_object = dict(center=[0.0, -0.25, 0.0], radius=0.25)
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
