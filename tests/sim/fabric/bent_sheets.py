"""Shapes imposed on a flat grid for bending tests, and a dihedral-hinge sum to compare
other bending models with."""

import math

import numpy as np


def cylinder(grid, radius, degrees):
    """The flat sheet rolled, without stretching, onto a cylinder whose axis makes `degrees`
    with the grid's x axis."""
    p = grid.rest_positions()
    th = math.radians(degrees)
    axis, across = np.array([math.cos(th), math.sin(th)]), np.array([-math.sin(th),
                                                                     math.cos(th)])
    t = p[:, 0] * axis[0] + p[:, 2] * axis[1]
    s = p[:, 0] * across[0] + p[:, 2] * across[1]
    x = np.empty_like(p)
    x[:, 0] = t * axis[0] + radius * np.sin(s / radius) * across[0]
    x[:, 2] = t * axis[1] + radius * np.sin(s / radius) * across[1]
    x[:, 1] = radius * (1 - np.cos(s / radius))
    return x


def hinge_sum(x, grid):
    """Σ l_e² θ_e² / (A₁ + A₂) over the interior edges of the triangulation with one diagonal,
    (i, j+1)–(i+1, j), per cell: θ the angle between the two triangles' normals, l and A the
    rest edge length and triangle areas. Hinge models are this sum times a coefficient."""
    idx = np.arange(grid.num_particles).reshape(grid.shape)
    a, b, c, d = (idx[:-1, :-1].ravel(), idx[:-1, 1:].ravel(), idx[1:, :-1].ravel(),
                  idx[1:, 1:].ravel())
    tris = np.concatenate([np.stack([a, c, b], 1), np.stack([b, c, d], 1)])
    rest = grid.rest_positions()
    sides = {}
    for t, tri in enumerate(tris):
        for k in range(3):
            e = tuple(sorted((tri[k], tri[(k + 1) % 3])))
            sides.setdefault(e, []).append(t)

    def normal(pts, tri):
        n = np.cross(pts[tri[1]] - pts[tri[0]], pts[tri[2]] - pts[tri[0]])
        return n / np.linalg.norm(n), 0.5 * np.linalg.norm(n)

    total = 0.0
    for (i, j), ts in sides.items():
        if len(ts) == 2:
            (n1, _), (n2, _) = normal(x, tris[ts[0]]), normal(x, tris[ts[1]])
            theta = math.acos(min(1.0, max(-1.0, float(n1 @ n2))))
            area = normal(rest, tris[ts[0]])[1] + normal(rest, tris[ts[1]])[1]
            total += float(np.sum((rest[i] - rest[j]) ** 2)) * theta ** 2 / area
    return total
