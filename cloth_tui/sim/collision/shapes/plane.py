"""An infinite plane through the centre, facing `normal`. It cannot be walked around, so
each particle keeps the side it started on (the collider records it): two-sided."""

from __future__ import annotations


import numpy as np

from ....object_shapes import PLANE
from .base import DIRECTION, Shape, unit

RENDER_HALF = 0.9  # m: shown extent of the plane, about the sheet's
USD_HALF = 1.0     # m: half the side of the quad that shows it in a bake


def distance(qx, qy, qz, p, side, grid, gradient):
    nx, ny, nz = side * p[3], side * p[4], side * p[5]
    return qx * nx + qy * ny + qz * nz, nx, ny, nz


def quad(center, normal, half: float) -> np.ndarray:
    """Four corners of a square about `center`, counter-clockwise seen from the side the
    normal points to."""
    n = np.asarray(normal, dtype=np.float64)
    n = n / np.linalg.norm(n)
    helper = np.array([1.0, 0.0, 0.0]) if abs(n[0]) < 0.9 else np.array([0.0, 0.0, 1.0])
    u = np.cross(n, helper)
    u /= np.linalg.norm(u)
    v = np.cross(n, u)
    c = np.asarray(center, dtype=np.float64)
    return np.array([c + half * (su * u + sv * v)
                     for su, sv in ((-1, -1), (1, -1), (1, 1), (-1, 1))])


class Plane(Shape):
    name = "plane"
    code = 3
    keys = PLANE.keys
    parameter_kinds = {"normal": DIRECTION}
    single_object = PLANE.single_object
    sided = True
    faint = True
    distance = staticmethod(distance)

    def parameters(self, obj) -> dict:
        return {"normal": unit(obj.normal)}

    def pack(self, parameters: dict) -> tuple:
        return parameters["normal"]

    def sides(self, q: np.ndarray, packed: tuple) -> np.ndarray:
        return np.where(q @ np.asarray(packed[0:3]) >= 0.0, 1.0, -1.0)

    def render_mesh(self, pv, parameters: dict):
        return pv.Plane(direction=parameters["normal"], i_size=2 * RENDER_HALF,
                        j_size=2 * RENDER_HALF)

    def define_usd(self, usd, stage, path: str, parameters: dict) -> None:
        UsdGeom, Vt = usd.UsdGeom, usd.Vt
        shape = UsdGeom.Mesh.Define(stage, path)
        corners = quad((0.0, 0.0, 0.0), parameters["normal"], USD_HALF)
        shape.CreatePointsAttr(Vt.Vec3fArray.FromNumpy(corners.astype(np.float32)))
        shape.CreateFaceVertexCountsAttr(Vt.IntArray([4]))
        shape.CreateFaceVertexIndicesAttr(Vt.IntArray([0, 1, 2, 3]))
        shape.CreateSubdivisionSchemeAttr(UsdGeom.Tokens.none)
        shape.CreateDoubleSidedAttr(True)


SHAPE = Plane()
