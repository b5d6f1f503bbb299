"""The implicit-Euler objective of a fabric step and its gradient, in one nogil kernel:

    Φ(x) = Σ m_i |x_i − y_i|² / (2h²) + Σ_edges (l − l0)²/(2α_e) + Σ_cells γ²/(2α_c)
           + Σ_stencils |D_s x|²/(2α_s)

(the same energies fabric_solve.fabric_energy sums; y the substep's prediction). A fixed
particle (inv_mass 0) has zero gradient."""

from __future__ import annotations

import math

from cloth_tui.sim.jit import kernel


@kernel()
def objective(x, y, mass_h2, inv_mass, edges, rest, k_edge, alive, cells, cell_alive, k_cell,
              scale, sp, sc, k_sten, sten_alive, grad, want_grad, theta):
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
    for s in range(sp.shape[0]):
        if not sten_alive[s]:
            continue
        cx = 0.0
        cy = 0.0
        cz = 0.0
        for k in range(4):
            p = sp[s, k]
            cx += sc[s, k] * x[p, 0]
            cy += sc[s, k] * x[p, 1]
            cz += sc[s, k] * x[p, 2]
        ks = k_sten[s]
        phi += 0.5 * ks * (cx * cx + cy * cy + cz * cz)
        if want_grad:
            for k in range(4):
                p = sp[s, k]
                f = ks * sc[s, k]
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
            grad[i, 0] = theta * grad[i, 0] + mass_h2[i] * dx
            grad[i, 1] = theta * grad[i, 1] + mass_h2[i] * dy
            grad[i, 2] = theta * grad[i, 2] + mass_h2[i] * dz
    if want_grad:
        for i in range(n):
            if inv_mass[i] == 0.0:
                grad[i, 0] = 0.0
                grad[i, 1] = 0.0
                grad[i, 2] = 0.0
    return phi
