"""Linearised backward Euler for the springs solver: the system and its CG solve.

    (M − h²K − hD) Δv = h (f + h K v),  v' = v + Δv,  x' = x + h v'

K = ∂f/∂x, D = ∂f/∂v of the springs and the drag (see integrators.py for the model). The
transverse part of each spring's K is clamped to tension (max(0, 1 − L0/L)) so the matrix
stays symmetric positive definite; it is solved matrix-free by Jacobi-preconditioned
conjugate gradients, warm-started from the last substep's Δv.
"""

from __future__ import annotations

import math


from ...jit import kernel

DEGENERATE_LENGTH = 1e-12  # m: a spring this short has no direction and exerts no force
CG_TOLERANCE = 1e-6        # relative residual ‖r‖/‖b‖ at which conjugate gradients stops
CG_MAX_ITERATIONS = 400    # cap per substep; a stiff, large sheet may stop here (still stable)


@kernel()
def _spring_jacobian(x, edges, rest, alive, dirs, tension):
    """Per spring: unit direction n and the clamped transverse factor max(0, 1 − L0/L). A torn
    or degenerate spring gets n = 0, s = 0: its block of the system vanishes."""
    for e in range(edges.shape[0]):
        a = edges[e, 0]
        b = edges[e, 1]
        dx = x[b, 0] - x[a, 0]
        dy = x[b, 1] - x[a, 1]
        dz = x[b, 2] - x[a, 2]
        L = math.sqrt(dx * dx + dy * dy + dz * dz)
        if L < DEGENERATE_LENGTH or not alive[e]:
            dirs[e, 0] = 0.0
            dirs[e, 1] = 0.0
            dirs[e, 2] = 0.0
            tension[e] = 0.0
            continue
        dirs[e, 0] = dx / L
        dirs[e, 1] = dy / L
        dirs[e, 2] = dz / L
        tension[e] = max(0.0, 1.0 - rest[e] / L)


@kernel(inline="always")
def _spring_block_product(p, a, b, nx, ny, nz, s, ck, cd):
    """One spring's block of the system times (p_a − p_b):
    (ck·[n nᵀ + s (I − n nᵀ)] + cd·n nᵀ)(p_a − p_b), the stiffness part with the transverse
    term s clamped to tension, the damping part along the spring only."""
    ux = p[a, 0] - p[b, 0]
    uy = p[a, 1] - p[b, 1]
    uz = p[a, 2] - p[b, 2]
    nu = nx * ux + ny * uy + nz * uz
    axial = ck * (1.0 - s) * nu + cd * nu
    return ck * s * ux + axial * nx, ck * s * uy + axial * ny, ck * s * uz + axial * nz


@kernel()
def _apply_system(p, y, edges, dirs, tension, diag_mass, free, ck, cd):
    """y = A p with A = diag_mass − ck·K̂ − cd·D̂ on the free particles, identity on pinned.
    K̂ per spring is [n nᵀ + s (I − n nᵀ)] coupling a and b (ck = h²k), D̂ = n nᵀ (cd = h·kd)."""
    for i in range(p.shape[0]):
        if free[i]:
            y[i, 0] = diag_mass[i] * p[i, 0]
            y[i, 1] = diag_mass[i] * p[i, 1]
            y[i, 2] = diag_mass[i] * p[i, 2]
        else:
            y[i, 0] = p[i, 0]
            y[i, 1] = p[i, 1]
            y[i, 2] = p[i, 2]
    for e in range(edges.shape[0]):
        a = edges[e, 0]
        b = edges[e, 1]
        wx, wy, wz = _spring_block_product(p, a, b, dirs[e, 0], dirs[e, 1], dirs[e, 2],
                                           tension[e], ck, cd)
        if free[a]:
            y[a, 0] += wx
            y[a, 1] += wy
            y[a, 2] += wz
        if free[b]:
            y[b, 0] -= wx
            y[b, 1] -= wy
            y[b, 2] -= wz


@kernel()
def solve_implicit_euler(x, v, accel, mass, free, edges, rest, alive, k, kd, drag, h,
                         dirs, tension, dv, r, z, p, q, diag, tol, max_iter):
    """Linearised backward Euler: solve (M − h²K − hD) Δv = h (f + h K v) for Δv by
    Jacobi-preconditioned CG, then v += Δv, x += h v. Returns the CG iterations used."""
    n = x.shape[0]
    _spring_jacobian(x, edges, rest, alive, dirs, tension)
    ck = h * h * k
    cd = h * kd
    dm = 1.0 + h * drag
    # right-hand side h (f + h K v), f = m·accel (accel already holds springs, drag and the
    # external forces); the Jacobi diagonal of the system alongside
    for i in range(n):
        for c in range(3):
            r[i, c] = h * mass[i] * accel[i, c] if free[i] else 0.0
            diag[i, c] = mass[i] * dm if free[i] else 1.0
    for e in range(edges.shape[0]):
        a = edges[e, 0]
        b = edges[e, 1]
        nx = dirs[e, 0]
        ny = dirs[e, 1]
        nz = dirs[e, 2]
        s = tension[e]
        # h² (K v)_a = −h² k [n nᵀ + s (I − n nᵀ)] (v_a − v_b)
        wx, wy, wz = _spring_block_product(v, a, b, nx, ny, nz, s, ck, 0.0)
        dxx = ck * (s + (1.0 - s) * nx * nx) + cd * nx * nx
        dyy = ck * (s + (1.0 - s) * ny * ny) + cd * ny * ny
        dzz = ck * (s + (1.0 - s) * nz * nz) + cd * nz * nz
        if free[a]:
            r[a, 0] -= wx
            r[a, 1] -= wy
            r[a, 2] -= wz
            diag[a, 0] += dxx
            diag[a, 1] += dyy
            diag[a, 2] += dzz
        if free[b]:
            r[b, 0] += wx
            r[b, 1] += wy
            r[b, 2] += wz
            diag[b, 0] += dxx
            diag[b, 1] += dyy
            diag[b, 2] += dzz
    # CG warm-started from the previous substep's Δv (accelerations change little from one
    # substep to the next): r = b − A Δv
    bnorm2 = 0.0
    finite = True
    for i in range(n):
        for c in range(3):
            bnorm2 += r[i, c] * r[i, c]
            finite = finite and math.isfinite(dv[i, c])
    if bnorm2 == 0.0 or not finite:
        dv[...] = 0.0
    dmass = mass * dm
    _apply_system(dv, q, edges, dirs, tension, dmass, free, ck, cd)
    rz = 0.0
    for i in range(n):
        for c in range(3):
            if not free[i]:
                dv[i, c] = 0.0
            r[i, c] -= q[i, c] if free[i] else 0.0
            z[i, c] = r[i, c] / diag[i, c]
            p[i, c] = z[i, c]
            rz += r[i, c] * z[i, c]
    it = 0
    if bnorm2 > 0.0:
        stop2 = tol * tol * bnorm2
        rr = 0.0
        for i in range(n):
            for c in range(3):
                rr += r[i, c] * r[i, c]
        while it < max_iter and rr > stop2:
            _apply_system(p, q, edges, dirs, tension, dmass, free, ck, cd)
            pq = 0.0
            for i in range(n):
                for c in range(3):
                    pq += p[i, c] * q[i, c]
            if pq <= 0.0:
                break
            alpha = rz / pq
            rr = 0.0
            for i in range(n):
                for c in range(3):
                    dv[i, c] += alpha * p[i, c]
                    r[i, c] -= alpha * q[i, c]
                    rr += r[i, c] * r[i, c]
            it += 1
            if rr <= stop2:
                break
            rz_new = 0.0
            for i in range(n):
                for c in range(3):
                    z[i, c] = r[i, c] / diag[i, c]
                    rz_new += r[i, c] * z[i, c]
            beta = rz_new / rz
            rz = rz_new
            for i in range(n):
                for c in range(3):
                    p[i, c] = z[i, c] + beta * p[i, c]
    for i in range(n):
        if free[i]:
            for c in range(3):
                v[i, c] += dv[i, c]
                x[i, c] += h * v[i, c]
    return it
