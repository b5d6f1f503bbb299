"""Projecting a material's constraints (fabric.py) in XPBD form: its structural edges by the
colour sweeps with α̃ per edge, its shear cells and its bending stencils by the loops here.

Each pass of a substep projects the stencils, then the cells, then the edges, and the passes
repeat `iterations` times, each family going on with its own λ: Gauss-Seidel
over all of them, the stiff stretch last so a frame ends closest to it. For a constraint C
with gradient ∇C and compliance α (α̃ = α/h²), every projection is

    Δλ = (−C − α̃λ) / (Σ_k w_k |∇_k C|² + α̃),   λ += Δλ,   x_k += w_k ∇_k C Δλ.

A cell's C = γ = (|d₁|² − |d₂|²)/(4·dx·dz) (d₁ = x₃ − x₀, d₂ = x₂ − x₁) has ∇₃ = −∇₀ = 2d₁/(4dxdz)
and ∇₂ = −∇₁ = −2d₂/(4dxdz). A stencil's C = Σ_k c_k x_k is a 3-vector, linear in x, with
∇_k = c_k per component: its Δλ is a 3-vector with one scalar denominator.

The stencils start each substep from the last one's multipliers (a warm start): their
correction Σ w_k c_k λ is applied to the prediction first and the passes go on with λ. The
stencils are linear, so that is exactly the last substep's bending correction, and at rest
the bending solve starts at its answer and changes nothing: a settled strip bends as the
material's B says whatever the iterations. From λ = 0, passes that do not converge settle
where their partial correction balances the load, softer than the material the more its
bending per step, h²·B/(ρ_A·dx⁴), outweighs its masses (docs/physics.md, "Warm-started
bending"). The stiff stretch is not warm-started: carried over its unconverged passes, the
last substep's corrections along turned edges diverge.

A measured fabric's edges stiffen with strain: before the passes each edge takes the secant
α of its strain now (stretch_curve.py), so a held stretch pulls with the measured tension.
"""

from __future__ import annotations

import numpy as np

from ...jit import kernel
from ...fabric.stretch_curve import StrainStiffening
from .constraints import ProjectConstraints


@kernel()
def project_cells(x, inv_mass, cells, alive, lam, alpha_t, scale, fresh, iterations):
    """`iterations` passes over the shear cells (corners (i, j), (i, j+1), (i+1, j),
    (i+1, j+1)); `scale` = 1/(4·dx·dz); skipped where alive[c] == 0."""
    if fresh:
        lam[:] = 0.0
    g = 2.0 * scale
    for _ in range(iterations):
        for c in range(cells.shape[0]):
            if not alive[c]:
                continue
            p0, p1, p2, p3 = cells[c, 0], cells[c, 1], cells[c, 2], cells[c, 3]
            w0, w1, w2, w3 = inv_mass[p0], inv_mass[p1], inv_mass[p2], inv_mass[p3]
            d1x = x[p3, 0] - x[p0, 0]
            d1y = x[p3, 1] - x[p0, 1]
            d1z = x[p3, 2] - x[p0, 2]
            d2x = x[p2, 0] - x[p1, 0]
            d2y = x[p2, 1] - x[p1, 1]
            d2z = x[p2, 2] - x[p1, 2]
            n1 = d1x * d1x + d1y * d1y + d1z * d1z
            n2 = d2x * d2x + d2y * d2y + d2z * d2z
            denom = g * g * (n1 * (w0 + w3) + n2 * (w1 + w2)) + alpha_t
            if denom == 0.0:
                continue
            dl = (-(n1 - n2) * scale - alpha_t * lam[c]) / denom
            lam[c] += dl
            s1 = g * dl
            x[p3, 0] += w3 * s1 * d1x
            x[p3, 1] += w3 * s1 * d1y
            x[p3, 2] += w3 * s1 * d1z
            x[p0, 0] -= w0 * s1 * d1x
            x[p0, 1] -= w0 * s1 * d1y
            x[p0, 2] -= w0 * s1 * d1z
            x[p1, 0] += w1 * s1 * d2x
            x[p1, 1] += w1 * s1 * d2y
            x[p1, 2] += w1 * s1 * d2z
            x[p2, 0] -= w2 * s1 * d2x
            x[p2, 1] -= w2 * s1 * d2y
            x[p2, 2] -= w2 * s1 * d2z


@kernel()
def project_stencils(x, inv_mass, particles, coeffs, alive, lam, alpha_t, fresh, iterations):
    """`iterations` passes over the bending stencils: C_s = Σ_k coeffs[s, k]·x[particles[s, k]]
    (a slot with coefficient 0 changes nothing), α̃ = alpha_t[s]; λ is (S, 3)."""
    if fresh:
        lam[:, :] = 0.0
    for _ in range(iterations):
        for s in range(particles.shape[0]):
            if not alive[s]:
                continue
            a = alpha_t[s]
            cx = 0.0
            cy = 0.0
            cz = 0.0
            denom = a
            for k in range(4):
                p = particles[s, k]
                c = coeffs[s, k]
                cx += c * x[p, 0]
                cy += c * x[p, 1]
                cz += c * x[p, 2]
                denom += inv_mass[p] * c * c
            if denom == 0.0:
                continue
            dx = (-cx - a * lam[s, 0]) / denom
            dy = (-cy - a * lam[s, 1]) / denom
            dz = (-cz - a * lam[s, 2]) / denom
            lam[s, 0] += dx
            lam[s, 1] += dy
            lam[s, 2] += dz
            for k in range(4):
                p = particles[s, k]
                wc = inv_mass[p] * coeffs[s, k]
                x[p, 0] += wc * dx
                x[p, 1] += wc * dy
                x[p, 2] += wc * dz


@kernel()
def warm_start_stencils(x, inv_mass, particles, coeffs, alive, lam):
    """Applies each live stencil's correction for its λ of the last substep, x_k += w_k c_k λ
    (the projection's own update with Δλ = λ); a torn one's λ is dropped."""
    for s in range(particles.shape[0]):
        if not alive[s]:
            lam[s, 0] = 0.0
            lam[s, 1] = 0.0
            lam[s, 2] = 0.0
            continue
        for k in range(4):
            p = particles[s, k]
            wc = inv_mass[p] * coeffs[s, k]
            x[p, 0] += wc * lam[s, 0]
            x[p, 1] += wc * lam[s, 1]
            x[p, 2] += wc * lam[s, 2]


class ProjectFabric:
    """The constraint stage of xpbd with a material (module docstring). Keeps each family's
    multipliers of the last substep: `lambdas` (N·s², one per model.edges constraint, as
    ProjectConstraints), `cell_lambdas` (C,) and `stencil_lambdas` (S, 3). With
    `levels` (hpbd's multiplier levels, hpbd/multiplier_levels.py), a coarse correction
    of the edges' λ follows each of the first half of the passes (the rest smooth what its
    blocks leave; at one pass there is none, and hpbd is xpbd)."""

    name = "project_fabric_constraints"

    def __init__(self, model, iterations: int, h: float, levels=None):
        f = model.fabric
        self.model = model
        self.fabric = f
        self.iterations = iterations
        self.edges = ProjectConstraints(model, 1, f.compliance, h, name="project_edges")
        self.cell_alpha_t = f.cell_compliance / (h * h)
        self.stencil_alpha_t = np.ascontiguousarray(f.stencil_compliance / (h * h))
        self.cell_lambdas = np.zeros(f.num_cells)
        self.stencil_lambdas = np.zeros((f.num_stencils, 3))
        self.cell_alive = np.ones(f.num_cells, np.uint8)
        self.stencil_alive = np.ones(f.num_stencils, np.uint8)
        self._scale = 1.0 / (4.0 * f.grid.dx * f.grid.dz)
        self._masks_torn = 0  # state.torn when the masks were last made
        self.stiffening = self._stiffening(f)
        self.hierarchy = levels
        if levels is not None:
            self.name = "project_fabric_levels"

    def retune(self, fabric, h: float) -> None:
        """Run on with `fabric`'s numbers (fabric.refit_fabric: the same constraints) and the
        model's masses as they are now."""
        self.fabric = fabric
        self.edges.set_compliance(fabric.compliance, h)
        self.edges.refresh_masses()
        self.cell_alpha_t = fabric.cell_compliance / (h * h)
        self.stencil_alpha_t = np.ascontiguousarray(fabric.stencil_compliance / (h * h))
        self.stiffening = self._stiffening(fabric)

    def _stiffening(self, fabric):
        if fabric.stretch is None:
            return None
        return StrainStiffening(fabric.stretch, self.model.edges, self.model.rest_length)

    @property
    def lambdas(self) -> np.ndarray:
        return self.edges.lambdas

    @property
    def alpha_t(self) -> np.ndarray:
        """α/h² of each model.edges constraint (ProjectConstraints' name for it)."""
        return self.edges.alpha_t

    alpha_tilde = alpha_t

    def apply(self, state, h):
        if state.torn or self._masks_torn:
            self._mask_torn(state.alive, state.torn)
        m, f = self.model, self.fabric
        has_edges = m.num_constraints > 0
        if self.stiffening is not None and has_edges:
            self.edges.set_compliance(self.stiffening.compliance(state.x), h)
        if f.stencils is not None:
            warm_start_stencils(state.x, m.inv_mass, f.stencils.particles, f.stencils.coeffs,
                                self.stencil_alive, self.stencil_lambdas)
        for it in range(self.iterations):
            fresh = it == 0
            if f.stencils is not None:
                project_stencils(state.x, m.inv_mass, f.stencils.particles, f.stencils.coeffs,
                                 self.stencil_alive, self.stencil_lambdas,
                                 self.stencil_alpha_t, False, 1)
            if f.num_cells:
                project_cells(state.x, m.inv_mass, f.cells, self.cell_alive, self.cell_lambdas,
                              self.cell_alpha_t, self._scale, fresh, 1)
            if has_edges:
                self.edges.project(state, 1, fresh)
                if self.hierarchy is not None and it < self.iterations // 2:
                    lam, edge_slot = self.edges.slot_lambdas
                    self.hierarchy.correct(state.x, m.inv_mass, m.rest_length, state.alive,
                                           self.edges.alpha_t, lam, edge_slot,
                                           assemble=it == 0)

    def _mask_torn(self, alive: np.ndarray, torn: int) -> None:
        """A cell or stencil across a torn edge leaves the solve with it: a torn flap is not
        held by the shear or bending of the sheet it left."""
        f = self.fabric
        intact = np.append(alive, 1).astype(bool)  # index −1 (no such edge) reads intact
        self.cell_alive[:] = intact[f.cell_edges].all(axis=1)
        self.stencil_alive[:] = intact[f.stencil_edges].all(axis=1)
        self._masks_torn = torn


def fabric_energy(x: np.ndarray, model) -> dict[str, float]:
    """J by family of positions x (N, 3) under the model's material constraints, Σ C²/(2α):
    what the solve minimises (with the inertia), for tests and the lab."""
    f = model.fabric
    e = model.edges
    length = np.linalg.norm(x[e[:, 1]] - x[e[:, 0]], axis=1)
    out = {"stretch": float(((length - model.rest_length) ** 2 / (2 * f.compliance)).sum())}
    if f.num_cells:
        c = f.cells
        d1, d2 = x[c[:, 3]] - x[c[:, 0]], x[c[:, 2]] - x[c[:, 1]]
        gamma = ((d1 * d1).sum(axis=1) - (d2 * d2).sum(axis=1)) / (4 * f.grid.dx * f.grid.dz)
        out["shear"] = float((gamma ** 2).sum() / (2 * f.cell_compliance))
    else:
        out["shear"] = 0.0
    if f.stencils is not None:
        d = f.stencils.apply(x)
        out["bending"] = float(((d * d).sum(axis=1) / (2 * f.stencil_compliance)).sum())
    else:
        out["bending"] = 0.0
    return out


def fabric_force_energy(projection: ProjectFabric, h: float) -> float:
    """J: Σ ½ α f² (f = λ/h²) over every constraint of the last substep, the solver's own
    estimate of the elastic energy (measures.py's for xpbd, extended to cells and stencils)."""
    p, f = projection, projection.fabric
    h2 = h * h
    total = float(np.dot(np.asarray(p.alpha_t) * h2, (p.lambdas / h2) ** 2))
    total += f.cell_compliance * float(((p.cell_lambdas / h2) ** 2).sum())
    if f.num_stencils:
        total += float(np.dot(f.stencil_compliance,
                              ((p.stencil_lambdas / h2) ** 2).sum(axis=1)))
    return 0.5 * total
