"""A closed triangle surface from a file, placed at the centre (the file's origin there),
scaled and rotated: its distance is sampled on a grid (cloth_tui.meshes builds it, outside
the physics), which the compiled distance reads trilinearly.

For a point q in the object's frame, with g = (q − origin)/cell its grid coordinates,
i = ⌊g⌋ and f = g − i, the distance is the trilinear blend of the cell's eight samples,

    d(q) = Σ_{a,b,c ∈ {0,1}} w_a(f_x) w_b(f_y) w_c(f_z) D[i_x+a, i_y+b, i_z+c],
    w_0(t) = 1 − t,  w_1(t) = t,

and the outward normal is the same blend of the samples' central-difference gradients,
normalised: n = ∇d / |∇d|. Outside the grid (which is padded beyond the skin) nothing
touches: d is reported as OUTSIDE. A bake records the triangles in the shape's prim, and
reading it back gives them again, so a replay draws the mesh without its file.
"""

from __future__ import annotations

import hashlib
import math

import numpy as np

from .... import meshes
from ....object_shapes import MESH
from .base import MAX_LENGTH, SURFACE, KernelInputs, Shape, ShapeValueError

OUTSIDE = 1e9    # m: the distance reported beyond the grid, where nothing touches
FLAT = 1e-12     # |∇d| below this has no direction of its own; choose up


def distance(qx, qy, qz, p, side, grid, gradient):
    """Trilinear distance and normalised gradient of the grid at q (object frame); p[3:6] is
    the grid's origin, p[6] 1/cell."""
    inv_cell = p[6]
    gx = (qx - p[3]) * inv_cell
    gy = (qy - p[4]) * inv_cell
    gz = (qz - p[5]) * inv_cell
    nx, ny, nz = grid.shape
    if not (0.0 <= gx <= nx - 1 and 0.0 <= gy <= ny - 1 and 0.0 <= gz <= nz - 1):
        return OUTSIDE, 0.0, 1.0, 0.0  # (also a NaN q: it fails every comparison)
    i = min(int(gx), nx - 2)
    j = min(int(gy), ny - 2)
    k = min(int(gz), nz - 2)
    fx, fy, fz = gx - i, gy - j, gz - k
    d = 0.0
    ux = uy = uz = 0.0
    for a in range(2):
        wa = fx if a else 1.0 - fx
        for b in range(2):
            wb = fy if b else 1.0 - fy
            for c in range(2):
                w = wa * wb * (fz if c else 1.0 - fz)
                d += w * grid[i + a, j + b, k + c]
                ux += w * gradient[i + a, j + b, k + c, 0]
                uy += w * gradient[i + a, j + b, k + c, 1]
                uz += w * gradient[i + a, j + b, k + c, 2]
    length = math.sqrt(ux * ux + uy * uy + uz * uz)
    if length < FLAT:
        return d, 0.0, 1.0, 0.0
    return d, ux / length, uy / length, uz / length


class Mesh(Shape):
    name = "mesh"
    code = 4
    keys = MESH.keys
    parameter_kinds = {"surface": SURFACE}
    distance = staticmethod(distance)

    def check_scene(self, objects: list) -> None:
        meshes.check_scene_meshes(objects)

    def kernel_inputs(self, obj, spacing: float, thickness: float, where: str) -> KernelInputs:
        field = meshes.field_for(obj, spacing, thickness, where=where)
        return KernelInputs({"surface": field.surface},
                            (*map(float, field.origin), 1.0 / field.cell),
                            field.distance, field.gradient)

    def render_mesh(self, pv, parameters: dict):
        surface = parameters["surface"]
        return pv.PolyData.from_regular_faces(surface.vertices, surface.faces)

    def render_key(self, parameters: dict) -> tuple:
        return (parameters["surface"].key,)

    def define_usd(self, usd, stage, path: str, parameters: dict) -> None:
        UsdGeom, Vt = usd.UsdGeom, usd.Vt
        surface = parameters["surface"]
        shape = UsdGeom.Mesh.Define(stage, path)
        shape.CreatePointsAttr(Vt.Vec3fArray.FromNumpy(
            np.asarray(surface.vertices, dtype=np.float32)))
        shape.CreateFaceVertexCountsAttr(Vt.IntArray([3] * len(surface.faces)))
        shape.CreateFaceVertexIndicesAttr(Vt.IntArray(
            np.asarray(surface.faces, dtype=np.int64).ravel().tolist()))
        shape.CreateSubdivisionSchemeAttr(UsdGeom.Tokens.none)

    def read_usd(self, prim) -> dict:
        """The triangles of the object's Shape mesh, checked (a bake is user input)."""
        shape = prim.GetChild("Shape")

        def attr(name):
            return shape.GetAttribute(name).Get() if shape and shape.GetAttribute(name) else None

        try:
            vertices = np.asarray(attr("points"), dtype=np.float64)
            counts = np.asarray(attr("faceVertexCounts"), dtype=np.int64)
            indices = np.asarray(attr("faceVertexIndices"), dtype=np.int64)
        except (TypeError, ValueError, OverflowError):
            vertices = counts = indices = np.zeros(0)
        if (vertices.ndim != 2 or vertices.shape[1:] != (3,) or counts.ndim != 1
                or len(counts) == 0 or not (counts == 3).all()):
            raise ShapeValueError("its Shape holds no triangle mesh (a bake made before "
                                  "bakes recorded a mesh's triangles: bake it again)")
        if len(counts) > meshes.MAX_TRIANGLES or indices.shape != (3 * len(counts),):
            raise ShapeValueError(f"its Shape has {len(counts)} triangles and "
                                  f"{indices.size} corner indices; at most "
                                  f"{meshes.MAX_TRIANGLES} triangles of 3 corners are read")
        if not np.all(np.isfinite(vertices)) or np.abs(vertices).max() > MAX_LENGTH:
            raise ShapeValueError(f"its Shape has points that are not finite or beyond "
                                  f"±{MAX_LENGTH:g} m")
        if indices.min() < 0 or indices.max() >= len(vertices):
            raise ShapeValueError("its Shape has corner indices outside its points")
        faces = indices.reshape(-1, 3)
        digest = hashlib.sha1(vertices.tobytes() + faces.tobytes()).hexdigest()[:16]
        return {"surface": meshes.MeshSurface(f"bake:{digest}", vertices, faces)}


SHAPE = Mesh()
