"""Candidate: projective dynamics (Bouaziz et al. 2014) with Chebyshev acceleration (Wang
2015) on the same matrix P as lbfgs (factored here): each iteration projects every edge to its rest
length and every shear cell's diagonals to their mean length (the local step), then solves
P x = M y/h² + Σ w Aᵀp (the global step). Its energy is PD's: the shear cell as the distance
of its diagonals from equal length (the same as the material's at small shear), the bending
exactly (linear stencils: in the matrix, projected to zero). NumPy for the local step: its
timings are not comparable; its error at equal solves is."""

from __future__ import annotations

from dataclasses import replace
from types import SimpleNamespace

import numpy as np
from scipy.sparse.linalg import splu

from cloth_tui.sim.solvers.lbfgs.step_matrix import shear_weight, step_matrix


class ChebyshevPD:
    name = "project_fabric_pd"

    def __init__(self, model, h: float, iterations: int, rho: float = 0.95, gamma: float = 0.9):
        f = model.fabric
        self.model = model
        self.iterations = iterations
        self.rho, self.gamma = rho, gamma
        self.k_edge = 1.0 / np.asarray(f.compliance)
        # PD's cell energy w/4·(|d₁| − |d₂|)² equals k_c γ²/2 at small shear for twice the
        # Gauss-Newton weight lbfgs's preconditioner gives each diagonal
        self.pd_fabric = replace(f, cell_compliance=f.cell_compliance / 2)
        self.w_shear = shear_weight(self.pd_fabric) if f.num_cells else 0.0
        self.k_sten = 1.0 / np.asarray(f.stencil_compliance)
        self._h = None

    def _global_rhs(self, x, y):
        m = self.model
        e, L0, k = m.edges, m.rest_length, self.k_edge
        rhs = (m.mass / self._h ** 2)[:, None] * y
        d = x[e[:, 1]] - x[e[:, 0]]
        p = d * (L0 / np.maximum(np.linalg.norm(d, axis=1), 1e-12))[:, None]
        np.add.at(rhs, e[:, 1], k[:, None] * p)
        np.add.at(rhs, e[:, 0], -k[:, None] * p)
        c = m.fabric.cells
        if len(c):
            d1, d2 = x[c[:, 3]] - x[c[:, 0]], x[c[:, 2]] - x[c[:, 1]]
            n1, n2 = np.linalg.norm(d1, axis=1), np.linalg.norm(d2, axis=1)
            r = 0.5 * (n1 + n2)
            p1, p2 = d1 * (r / n1)[:, None], d2 * (r / n2)[:, None]
            w = self.w_shear
            np.add.at(rhs, c[:, 3], w * p1)
            np.add.at(rhs, c[:, 0], -w * p1)
            np.add.at(rhs, c[:, 2], w * p2)
            np.add.at(rhs, c[:, 1], -w * p2)
        fixed = m.inv_mass == 0
        # P drops a held particle's column: its springs' pull on free neighbours goes here
        rhs -= self.coupling @ x[fixed]
        rhs[fixed] = x[fixed]
        return rhs

    def apply(self, state, h):
        if self._h != h:
            self._h = h
            m = self.model
            fields = {k: getattr(m, k) for k in ("num_particles", "edges", "mass")}
            pd_model = SimpleNamespace(**fields, fabric=self.pd_fabric, inv_mass=m.inv_mass)
            self.lu = splu(step_matrix(pd_model, self.k_edge, self.k_sten, h).tocsc())
            everyone_free = SimpleNamespace(**fields, fabric=self.pd_fabric,
                                            inv_mass=np.ones(len(m.mass)))
            full = step_matrix(everyone_free, self.k_edge, self.k_sten, h).tocsr()
            fixed = m.inv_mass == 0
            self.coupling = full[:, fixed].tolil()
            self.coupling[np.flatnonzero(fixed), :] = 0.0
            self.coupling = self.coupling.tocsr()
        y = state.x.copy()
        x, x_before = state.x.copy(), state.x.copy()
        omega = 1.0
        for k in range(self.iterations):
            x_hat = self.lu.solve(self._global_rhs(x, y))
            if k == 0:
                omega = 1.0
            elif k == 1:
                omega = 2.0 / (2.0 - self.rho ** 2)
            else:
                omega = 4.0 / (4.0 - self.rho ** 2 * omega)
            x_new = omega * (self.gamma * (x_hat - x) + x - x_before) + x_before
            x_before, x = x, x_new
        state.x[...] = x
