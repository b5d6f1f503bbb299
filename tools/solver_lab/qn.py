"""Candidate: implicit Euler on the fabric's exact energy, minimised by L-BFGS whose initial
inverse Hessian is a prefactored constant matrix P = M/h² + Σk AᵀA (stretch edges, shear
diagonals at their Gauss-Newton weight, the bending Hessian exactly): projective dynamics'
matrix used as a preconditioner (Liu, Bouaziz & Kavan 2017), so the low-frequency error goes
in one solve and the energy minimised is the material's own."""

from __future__ import annotations

import numpy as np
import scipy.sparse as sp
import scipy.sparse.linalg as sla
from energy import objective

from cloth_tui.sim.fabric.bending import bending_hessian


def fabric_matrix(model, h: float, alive=None, theta=1.0):
    f = model.fabric
    n = model.num_particles
    e = model.edges
    k = 1.0 / np.asarray(f.compliance)
    if alive is not None:
        k = k * alive
    free = model.inv_mass > 0
    rows = [e[:, 0], e[:, 1], e[:, 0], e[:, 1]]
    cols = [e[:, 1], e[:, 0], e[:, 0], e[:, 1]]
    vals = [-k, -k, k, k]
    if f.num_cells:
        c = f.cells
        dx, dz = f.grid.dx, f.grid.dz
        s = 1.0 / (4 * dx * dz)
        w = 4 * s * s * (dx * dx + dz * dz) / f.cell_compliance
        for a, b in ((c[:, 0], c[:, 3]), (c[:, 1], c[:, 2])):
            ww = np.full(len(a), w)
            rows += [a, b, a, b]
            cols += [b, a, a, b]
            vals += [-ww, -ww, ww, ww]
    if f.stencils is not None:
        r, cc, v = bending_hessian(f.stencils, f.material.bending, n)
        rows.append(r)
        cols.append(cc)
        vals.append(v)
    r = np.concatenate(rows)
    c = np.concatenate(cols)
    v = theta * np.concatenate(vals)
    keep = free[r] & free[c]  # a fixed particle's row and column: identity
    diag = np.where(free, model.mass / (h * h), 1.0)
    A = sp.coo_matrix((np.concatenate([v[keep], diag]),
                       (np.concatenate([r[keep], np.arange(n)]),
                        np.concatenate([c[keep], np.arange(n)]))), shape=(n, n)).tocsc()
    return A


class QuasiNewtonFabric:
    name = "quasi_newton_fabric"

    def __init__(self, model, h: float, iterations: int = 4, history: int = 5,
                 theta: float = 1.0):
        self.theta = theta
        f = model.fabric
        self.model = model
        self.iterations = iterations
        self.history = history
        self.k_edge = np.ascontiguousarray(1.0 / np.asarray(f.compliance))
        self.k_cell = 1.0 / f.cell_compliance if f.num_cells else 0.0
        self.scale = 1.0 / (4 * f.grid.dx * f.grid.dz)
        if f.stencils is not None:
            self.sp, self.sc = f.stencils.particles, f.stencils.coeffs
            self.k_sten = np.ascontiguousarray(1.0 / np.asarray(f.stencil_compliance))
        else:
            self.sp = np.zeros((0, 4), np.int64)
            self.sc = np.zeros((0, 4))
            self.k_sten = np.zeros(0)
        self.cell_alive = np.ones(f.num_cells, np.uint8)
        self.sten_alive = np.ones(len(self.k_sten), np.uint8)
        self._h = None
        self.lambdas = np.zeros(model.num_constraints)
        self.last_gradient = 0.0
        self.evaluations = 0

    def _prepare(self, h):
        if self._h == h:
            return
        self._h = h
        self.mass_h2 = self.model.mass / (h * h)
        self.lu = sla.splu(fabric_matrix(self.model, h, theta=self.theta),
                           permc_spec="MMD_AT_PLUS_A", options={"SymmetricMode": True})

    def phi(self, x, y, alive, grad, want, theta=None):
        theta = self.theta if theta is None else theta
        self.evaluations += 1
        m = self.model
        return objective(x, y, self.mass_h2, m.inv_mass, m.edges, m.rest_length, self.k_edge,
                         alive, self.model.fabric.cells, self.cell_alive, self.k_cell,
                         self.scale, self.sp, self.sc, self.k_sten, self.sten_alive, grad,
                         want, theta)

    def apply(self, state, h, target=None):
        self._prepare(h)
        y = state.x.copy() if target is None else target
        if self.theta < 1.0 and target is None:
            # θ-scheme: M(x⁺ − 2x + x⁻)/h² = −θ∇E(x⁺) − (1−θ)∇E(x⁻) + f
            before = state.x_prev - h * state.v
            g_before = np.empty_like(y)
            self.phi(before, before, state.alive, g_before, True, 1.0)
            y -= (1.0 - self.theta) * g_before / self.mass_h2[:, None]
            y[self.model.inv_mass == 0] = state.x[self.model.inv_mass == 0]
        x = state.x
        fixed = self.model.inv_mass == 0
        g = np.empty_like(x)
        phi = self.phi(x, y, state.alive, g, True)
        S, Y, R = [], [], []
        g_new = np.empty_like(x)
        trial = np.empty_like(x)
        for _ in range(self.iterations):
            q = g.ravel().copy()
            alphas = []
            for s, yv, rho in zip(reversed(S), reversed(Y), reversed(R)):
                a = rho * (s @ q)
                alphas.append(a)
                q -= a * yv
            r = self.lu.solve(q.reshape(-1, 3)).ravel()
            for (s, yv, rho), a in zip(zip(S, Y, R), reversed(alphas)):
                b = rho * (yv @ r)
                r += (a - b) * s
            d = -r.reshape(-1, 3)
            d[fixed] = 0.0
            slope = float((g * d).sum())
            if slope >= 0:
                d = -self.lu.solve(g)
                d[fixed] = 0.0
                slope = float((g * d).sum())
                S, Y, R = [], [], []
            step = 1.0
            for _ls in range(10):
                np.add(x, step * d, out=trial)
                phi_new = self.phi(trial, y, state.alive, g_new, True)
                if phi_new <= phi + 1e-4 * step * slope:
                    break
                step *= 0.5
            else:
                break
            sv = (trial - x).ravel()
            yv = (g_new - g).ravel()
            x[...] = trial
            sy = sv @ yv
            if sy > 1e-30:
                S.append(sv)
                Y.append(yv)
                R.append(1.0 / sy)
                if len(S) > self.history:
                    S.pop(0), Y.pop(0), R.pop(0)
            g, g_new = g_new, g
            phi = phi_new
        self.last_gradient = float(np.abs(g).max())
