"""The objective of one implicit step and its gradient, in nogil kernels:

    Φ(x) = Σ_i m_i |x_i − y_i|² / (2h²) + θ·E(x),
    E(x) = Σ_edges k_e (l − l0)²/2 + Σ_cells k_c γ²/2 + Σ_stencils k_s |D_s x|²/2,

with y the substep's prediction (after the contacts) and E the material's own energies
(fabric.py: k = 1/α per edge, shear cell and bending stencil, the same terms xpbd projects).
θ = 1 is implicit Euler. A held particle (inverse mass 0) has zero gradient: it stays where
the pins put it. Plus the vector arithmetic of L-BFGS's two loops, here so that no dot
product goes through a threaded BLAS (on a shared 2-core machine its spinning threads cost
more than the product)."""

from __future__ import annotations

import math

from ...jit import kernel


@kernel()
def step_objective(x, y, mass_h2, inv_mass, edges, rest, k_edge, alive, cells, cell_alive,
                   k_cell, scale, sten_p, sten_c, k_sten, sten_alive, theta, grad, want_grad):
    """Φ(x) (see the module docstring); with want_grad its gradient into grad (N, 3).
    A cell's γ = (|x₃ − x₀|² − |x₂ − x₁|²)·scale; a stencil's D_s x = Σ_k sten_c[s,k] x_{p_k}."""
    n = x.shape[0]
    phi = 0.0
    if want_grad:
        grad[:, :] = 0.0
    for e in range(edges.shape[0]):
        if not alive[e]:
            continue
        a = edges[e, 0]
        b = edges[e, 1]
        ex = x[b, 0] - x[a, 0]
        ey = x[b, 1] - x[a, 1]
        ez = x[b, 2] - x[a, 2]
        length = math.sqrt(ex * ex + ey * ey + ez * ez)
        s = length - rest[e]
        phi += 0.5 * k_edge[e] * s * s
        if want_grad and length > 0.0:
            f = k_edge[e] * s / length
            grad[b, 0] += f * ex
            grad[b, 1] += f * ey
            grad[b, 2] += f * ez
            grad[a, 0] -= f * ex
            grad[a, 1] -= f * ey
            grad[a, 2] -= f * ez
    for c in range(cells.shape[0]):
        if not cell_alive[c]:
            continue
        p0, p1, p2, p3 = cells[c, 0], cells[c, 1], cells[c, 2], cells[c, 3]
        d1x = x[p3, 0] - x[p0, 0]
        d1y = x[p3, 1] - x[p0, 1]
        d1z = x[p3, 2] - x[p0, 2]
        d2x = x[p2, 0] - x[p1, 0]
        d2y = x[p2, 1] - x[p1, 1]
        d2z = x[p2, 2] - x[p1, 2]
        g = (d1x * d1x + d1y * d1y + d1z * d1z - d2x * d2x - d2y * d2y - d2z * d2z) * scale
        phi += 0.5 * k_cell * g * g
        if want_grad:
            f = k_cell * g * 2.0 * scale
            grad[p3, 0] += f * d1x
            grad[p3, 1] += f * d1y
            grad[p3, 2] += f * d1z
            grad[p0, 0] -= f * d1x
            grad[p0, 1] -= f * d1y
            grad[p0, 2] -= f * d1z
            grad[p2, 0] -= f * d2x
            grad[p2, 1] -= f * d2y
            grad[p2, 2] -= f * d2z
            grad[p1, 0] += f * d2x
            grad[p1, 1] += f * d2y
            grad[p1, 2] += f * d2z
    for s in range(sten_p.shape[0]):
        if not sten_alive[s]:
            continue
        cx = 0.0
        cy = 0.0
        cz = 0.0
        for k in range(4):
            p = sten_p[s, k]
            cx += sten_c[s, k] * x[p, 0]
            cy += sten_c[s, k] * x[p, 1]
            cz += sten_c[s, k] * x[p, 2]
        ks = k_sten[s]
        phi += 0.5 * ks * (cx * cx + cy * cy + cz * cz)
        if want_grad:
            for k in range(4):
                p = sten_p[s, k]
                f = ks * sten_c[s, k]
                grad[p, 0] += f * cx
                grad[p, 1] += f * cy
                grad[p, 2] += f * cz
    phi *= theta
    for i in range(n):
        dx = x[i, 0] - y[i, 0]
        dy = x[i, 1] - y[i, 1]
        dz = x[i, 2] - y[i, 2]
        phi += 0.5 * mass_h2[i] * (dx * dx + dy * dy + dz * dz)
        if want_grad:
            if inv_mass[i] == 0.0:
                grad[i, 0] = 0.0
                grad[i, 1] = 0.0
                grad[i, 2] = 0.0
            else:
                grad[i, 0] = theta * grad[i, 0] + mass_h2[i] * dx
                grad[i, 1] = theta * grad[i, 1] + mass_h2[i] * dy
                grad[i, 2] = theta * grad[i, 2] + mass_h2[i] * dz
    return phi


@kernel()
def dot(a, b):
    """Σ a·b over two (N, 3) arrays (C-contiguous, read flat: the loop then vectorises)."""
    a, b = a.reshape(-1), b.reshape(-1)
    total = 0.0
    for i in range(a.shape[0]):
        total += a[i] * b[i]
    return total


@kernel()
def first_loop(q, s_hist, y_hist, rho, order, count, alphas):
    """L-BFGS's first loop, newest pair first: q ← q − α_k y_k, α_k = ρ_k s_kᵀq (the arrays
    C-contiguous, read flat)."""
    flat = q.reshape(-1)
    size = flat.shape[0]
    s_flat = s_hist.reshape(s_hist.shape[0], size)
    y_flat = y_hist.reshape(y_hist.shape[0], size)
    for j in range(count - 1, -1, -1):
        k = order[j]
        a = 0.0
        for i in range(size):
            a += s_flat[k, i] * flat[i]
        a *= rho[k]
        alphas[k] = a
        for i in range(size):
            flat[i] -= a * y_flat[k, i]


@kernel()
def second_loop(r, s_hist, y_hist, rho, order, count, alphas, fixed):
    """L-BFGS's second loop, oldest pair first: r ← r + (α_k − ρ_k y_kᵀr) s_k; then the
    direction −r, zero on held particles (the arrays C-contiguous, read flat)."""
    flat = r.reshape(-1)
    size = flat.shape[0]
    s_flat = s_hist.reshape(s_hist.shape[0], size)
    y_flat = y_hist.reshape(y_hist.shape[0], size)
    for j in range(count):
        k = order[j]
        b = 0.0
        for i in range(size):
            b += y_flat[k, i] * flat[i]
        c = alphas[k] - rho[k] * b
        for i in range(size):
            flat[i] += c * s_flat[k, i]
    for i in range(r.shape[0]):
        if fixed[i]:
            r[i, 0] = 0.0
            r[i, 1] = 0.0
            r[i, 2] = 0.0
        else:
            r[i, 0] = -r[i, 0]
            r[i, 1] = -r[i, 1]
            r[i, 2] = -r[i, 2]


@kernel()
def step_to(x, d, t, out):
    """out ← x + t·d (C-contiguous, read flat)."""
    xf, df, of = x.reshape(-1), d.reshape(-1), out.reshape(-1)
    for i in range(xf.shape[0]):
        of[i] = xf[i] + t * df[i]


@kernel()
def edge_multipliers(x, edges, rest, k_edge, alive, h2, out):
    """XPBD's multiplier of each edge for the force the solved step leaves in it,
    λ = h²·k·(l0 − l) (N·s²; negative when stretched, as tearing by strength reads it)."""
    for e in range(edges.shape[0]):
        if not alive[e]:
            out[e] = 0.0
            continue
        a = edges[e, 0]
        b = edges[e, 1]
        ex = x[b, 0] - x[a, 0]
        ey = x[b, 1] - x[a, 1]
        ez = x[b, 2] - x[a, 2]
        out[e] = h2 * k_edge[e] * (rest[e] - math.sqrt(ex * ex + ey * ey + ez * ez))
