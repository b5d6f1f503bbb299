"""A mesh as a collider: the signed-distance grid of cloth_tui.meshes, sampled in a kernel.

For a point q in the object's frame, with g = (q − origin)/cell its grid coordinates,
i = ⌊g⌋ and f = g − i, the distance is the trilinear blend of the cell's eight samples,

    d(q) = Σ_{a,b,c ∈ {0,1}} w_a(f_x) w_b(f_y) w_c(f_z) D[i_x+a, i_y+b, i_z+c],
    w_0(t) = 1 − t,  w_1(t) = t,

and the outward normal is the same blend of the samples' central-difference gradients,
normalised: n = ∇d / |∇d|. Contact and friction are the other shapes' (colliders.py): a
particle with d < thickness moves out by thickness − d along n, and the contact's depth and
normal feed the Coulomb stage. Outside the grid (which is padded beyond the skin) nothing
touches: d is reported as OUTSIDE.
"""

from __future__ import annotations

import math

import numpy as np

from .. import meshes
from ..meshes import MeshField
from .colliders import ShapeCollider, orbit_offset, push_out_of_contact
from .jit import kernel
from .protocols import ObjectPose

MESH = 4         # shape code, beside colliders.SHAPES (the mesh samples a grid instead)
OUTSIDE = 1e9    # m: the distance reported beyond the grid, where nothing touches
FLAT = 1e-12     # |∇d| below this has no direction of its own; choose up


@kernel(inline="always")
def _mesh_distance(qx, qy, qz, origin, inv_cell, dist, grad):
    """Trilinear distance and normalised gradient of the grid at q (object frame)."""
    gx = (qx - origin[0]) * inv_cell
    gy = (qy - origin[1]) * inv_cell
    gz = (qz - origin[2]) * inv_cell
    nx, ny, nz = dist.shape
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
                d += w * dist[i + a, j + b, k + c]
                ux += w * grad[i + a, j + b, k + c, 0]
                uy += w * grad[i + a, j + b, k + c, 1]
                uz += w * grad[i + a, j + b, k + c, 2]
    length = math.sqrt(ux * ux + uy * uy + uz * uz)
    if length < FLAT:
        return d, 0.0, 1.0, 0.0
    return d, ux / length, uy / length, uz / length


@kernel()
def collide_mesh(x, inv_mass, center, origin, inv_cell, dist, grad, thickness, depth,
                 normal):
    """Contact projection against the mesh centred at `center` (see colliders.collide_shape)."""
    for i in range(x.shape[0]):
        if inv_mass[i] == 0.0:
            continue
        d, nx, ny, nz = _mesh_distance(x[i, 0] - center[0], x[i, 1] - center[1],
                                       x[i, 2] - center[2], origin, inv_cell, dist, grad)
        if d < thickness:
            push_out_of_contact(x, i, d, nx, ny, nz, thickness, depth, normal)


@kernel()
def mesh_signed_distances(x, center, origin, inv_cell, dist, grad, out):
    """out[i] = the grid's distance of point i (the one the contact kernel uses), m."""
    for i in range(x.shape[0]):
        d, _, _, _ = _mesh_distance(x[i, 0] - center[0], x[i, 1] - center[1],
                                    x[i, 2] - center[2], origin, inv_cell, dist, grad)
        out[i] = d


class MeshCollider(ShapeCollider):
    """A mesh placed at `center` (its file's origin there), static or moving along the
    orbit; its shape is the distance grid `field` (built outside sim, in cloth_tui.meshes)."""

    def __init__(self, model, field: MeshField, center, *, friction=0.9, thickness=0.005,
                 moving=False):
        super().__init__(model, "collide_mesh", MESH, center, friction, thickness)
        self.field, self.moving = field, moving
        self._inv_cell = 1.0 / field.cell

    def center_at(self, t: float) -> np.ndarray:
        return self.center0 + orbit_offset(t) if self.moving else self.center0

    def apply(self, state, h):
        self.center = self.center_at(state.t + h)
        f = self.field
        collide_mesh(state.x, self.inv_mass, self.center, f.origin, self._inv_cell, f.distance,
                     f.gradient, self.thickness, self.depth, self.normal_at)

    def signed_distance(self, x: np.ndarray) -> np.ndarray:
        f = self.field
        out = np.empty(len(x))
        mesh_signed_distances(np.ascontiguousarray(x, dtype=np.float64), self.center, f.origin,
                              self._inv_cell, f.distance, f.gradient, out)
        return out

    def pose(self, t: float) -> ObjectPose:
        c = self.center_at(t)
        return ObjectPose("mesh", tuple(float(v) for v in c), surface=self.field.surface)


def build_mesh_colliders(scene, model) -> list[MeshCollider]:
    """A collider for each `type = "mesh"` object of the scene, its grid sized to the sheet."""
    s = scene.scene
    meshes.check_scene_meshes([(f"objects[{k}]", o) for k, o in enumerate(scene.objects)
                               if o.type == "mesh"])
    out = []
    for k, o in enumerate(scene.objects):
        if o.type != "mesh":
            continue
        field = meshes.field_for(o, model.spacing, s.thickness, where=f"objects[{k}]")
        out.append(MeshCollider(model, field, o.center, thickness=s.thickness,
                                friction=s.friction if o.friction < 0 else o.friction,
                                moving=o.motion == "orbit"))
    return out
