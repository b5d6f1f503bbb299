"""How far a frame's solve ends from its step's own minimum, and what did not close the gap.

    OPENBLAS_NUM_THREADS=1 python tools/solver_lab/solve_gap.py [CELLS]

The sheet is the fabric bench's (cloth_tui/bench/fabric_cost.py): 1 m of denim held by two
clips, released flat. It runs 30 frames (0.5 s) at one substep a frame, adaptive off. Each
row gives ms a frame (a kernel's first compile falls in its first row) and the largest
distance of a particle from the same run solved to convergence (lbfgs at 300 iterations a
step; 100 and 300 differ by about 6 mm). The rows:

- lbfgs at 2, 4 and 8 iterations (the registered solver);
- lbfgs with its constant matrix P built from the edges' stiffness scaled by β < 1: a softer
  P resists the sheet's turning less and its stretch less well too;
- lbfgs followed by one or two per-vertex Newton sweeps (vertex block descent's step: each
  particle's 3 × 3 Hessian knows its edges' directions, which P does not);
- Newton's method with the edges' Gauss-Newton Hessian along their current directions
  (3N × 3N, factored every iteration), at 32 cells and fewer only: its factor is slow.

Then the two readings of the solve error at 1, 2 and 4 substeps as the grid refines: lbfgs's
(the last iteration's largest move over the shortest rest length) and the largest change of
an edge vector over its rest length (blind to the sheet's translation, not to its turning).
docs/physics.md (lbfgs: what did not close the gap) has what this printed.
"""

from __future__ import annotations

import math
import sys
import time

import numpy as np
import scipy.sparse as sp
from numba import njit
from scipy.sparse.linalg import splu

from cloth_tui.bench.fabric_cost import clipped_fabric_scene
from cloth_tui.sim.run.runner import Simulation
from cloth_tui.sim.solvers.lbfgs import solver as lbfgs
from cloth_tui.sim.solvers.lbfgs import step_matrix as matrices
from cloth_tui.sim.solvers.lbfgs.step_energy import dot, edge_multipliers, step_to

FRAMES = 30


def incidence(n: int, index: np.ndarray):
    """Per particle, the rows of `index` (M, k) it appears in and where: CSR (ptr, row, slot)."""
    m, k = index.shape
    rows = np.repeat(np.arange(m), k)
    slots = np.tile(np.arange(k), m)
    who = index.ravel()
    order = np.argsort(who, kind="stable")
    ptr = np.concatenate([[0], np.cumsum(np.bincount(who, minlength=n))])
    return ptr.astype(np.int64), rows[order].astype(np.int64), slots[order].astype(np.int64)


@njit(cache=True)
def vertex_newton_sweep(x, y, mass_h2, inv_mass, edges, rest, k_edge, cells, k_cell, scale,
                        sten_p, sten_c, k_sten, e_ptr, e_row, e_slot, c_ptr, c_row, c_slot,
                        s_ptr, s_row, s_slot):
    """One Gauss-Seidel sweep of per-particle Newton steps on the step's objective: the
    particle's gradient and 3 × 3 Hessian (inertia, its edges along their directions with the
    geometric term clamped at zero, its shear cells, its bending stencils), solved by Cholesky."""
    H = np.zeros((3, 3))
    g = np.zeros(3)
    d = np.zeros(3)
    for i in range(x.shape[0]):
        if inv_mass[i] == 0.0:
            continue
        for a in range(3):
            g[a] = mass_h2[i] * (x[i, a] - y[i, a])
            for b in range(3):
                H[a, b] = mass_h2[i] if a == b else 0.0
        for t in range(e_ptr[i], e_ptr[i + 1]):
            e = e_row[t]
            j = edges[e, 1] if e_slot[t] == 0 else edges[e, 0]
            length = 0.0
            for a in range(3):
                d[a] = x[i, a] - x[j, a]
                length += d[a] * d[a]
            length = math.sqrt(length)
            k = k_edge[e]
            geometric = max(0.0, 1.0 - rest[e] / length)
            for a in range(3):
                d[a] /= length
                g[a] += k * (length - rest[e]) * d[a]
            for a in range(3):
                for b in range(3):
                    H[a, b] += k * (1.0 - geometric) * d[a] * d[b]
                H[a, a] += k * geometric
        for t in range(c_ptr[i], c_ptr[i + 1]):
            c = c_row[t]
            p0, p1, p2, p3 = cells[c, 0], cells[c, 1], cells[c, 2], cells[c, 3]
            n1 = 0.0
            n2 = 0.0
            for a in range(3):
                n1 += (x[p3, a] - x[p0, a]) ** 2
                n2 += (x[p2, a] - x[p1, a]) ** 2
            gamma = (n1 - n2) * scale
            slot = c_slot[t]
            first = slot == 0 or slot == 3  # on the diagonal p0-p3, else on p1-p2
            sign = 1.0 if slot == 3 or slot == 1 else -1.0
            for a in range(3):
                d[a] = x[p3, a] - x[p0, a] if first else x[p2, a] - x[p1, a]
            force = k_cell * gamma * 2.0 * scale
            curvature = max(0.0, force if first else -force)
            for a in range(3):
                g[a] += sign * force * d[a]
                for b in range(3):
                    H[a, b] += k_cell * 4.0 * scale * scale * d[a] * d[b]
                H[a, a] += curvature
        for t in range(s_ptr[i], s_ptr[i + 1]):
            s = s_row[t]
            c_i = sten_c[s, s_slot[t]]
            for a in range(3):
                bend = 0.0
                for q in range(4):
                    bend += sten_c[s, q] * x[sten_p[s, q], a]
                g[a] += k_sten[s] * c_i * bend
                H[a, a] += k_sten[s] * c_i * c_i
        step = np.linalg.solve(H, g)
        for a in range(3):
            x[i, a] -= step[a]


class VertexSweeps:
    """A stage after lbfgs's solve: `sweeps` vertex Newton sweeps on the same step's objective
    (its prediction and masses over h², read from the solve)."""

    name = "vertex_sweeps"

    def __init__(self, solve: lbfgs.SolveImplicitStep, sweeps: int):
        m = solve.model
        n = m.num_particles
        self.solve, self.sweeps = solve, sweeps
        self.incidence = (incidence(n, m.edges) + incidence(n, solve.cells)
                          + incidence(n, solve.sten_p))

    def apply(self, state, substep: float):
        s, m = self.solve, self.solve.model
        for _ in range(self.sweeps):
            vertex_newton_sweep(state.x, s._y, s.mass_h2, m.inv_mass, m.edges, m.rest_length,
                                s.k_edge, s.cells, s.k_cell, s.scale, s.sten_p, s.sten_c,
                                s.k_sten, *self.incidence)


@njit(cache=True)
def edge_blocks(x, edges, rest, k_edge):
    """Each edge's 3 × 3 Gauss-Newton block k(d dᵀ + max(0, 1 − l0/l)(I − d dᵀ))."""
    blocks = np.zeros((edges.shape[0], 3, 3))
    for e in range(edges.shape[0]):
        d = x[edges[e, 1]] - x[edges[e, 0]]
        length = math.sqrt(d[0] * d[0] + d[1] * d[1] + d[2] * d[2])
        d /= length
        geometric = max(0.0, 1.0 - rest[e] / length)
        for a in range(3):
            for b in range(3):
                blocks[e, a, b] = k_edge[e] * (1.0 - geometric) * d[a] * d[b]
            blocks[e, a, a] += k_edge[e] * geometric
    return blocks


class NewtonStep(lbfgs.SolveImplicitStep):
    """Newton's method on the step's objective: the edges' blocks along their directions, the
    rest of P (masses, shear diagonals, bending) on x, y and z alike, an Armijo line search."""

    def hessian(self, x, h: float):
        m = self.model
        n = m.num_particles
        blocks = edge_blocks(x, m.edges, m.rest_length, self.k_edge)
        axis = np.arange(3)
        rows, cols, vals = [], [], []
        a, b = m.edges[:, 0], m.edges[:, 1]
        for p, q, sign in ((a, a, 1.0), (b, b, 1.0), (a, b, -1.0), (b, a, -1.0)):
            rows.append(np.broadcast_to((3 * p)[:, None, None] + axis[:, None], blocks.shape))
            cols.append(np.broadcast_to((3 * q)[:, None, None] + axis[None, :], blocks.shape))
            vals.append(sign * blocks)
        rest = matrices.step_matrix(m, np.zeros_like(self.k_edge), self.k_sten, h).tocoo()
        for k in range(3):
            rows.append(3 * rest.row + k)
            cols.append(3 * rest.col + k)
            vals.append(rest.data)
        r, c, v = (np.concatenate([np.ravel(z) for z in zs]) for zs in (rows, cols, vals))
        free = np.repeat(m.inv_mass > 0, 3)
        keep = (free[r] & free[c]) | ((r == c) & ~free[r])
        return sp.coo_matrix((v[keep], (r[keep], c[keep])), shape=(3 * n, 3 * n)).tocsc()

    def apply(self, state, substep: float):
        h = substep * self.step_share
        self._prepare(state, h)
        x, y, alive = state.x, self._y, state.alive
        y[...] = x
        g, trial = self._g, self._trial
        phi = self.objective(x, y, alive, g, True)
        for _ in range(self.iterations):
            lu = splu(self.hessian(x, h), permc_spec="MMD_AT_PLUS_A")
            d = -lu.solve(g.ravel()).reshape(-1, 3)
            slope, t = dot(g, d), 1.0
            for _halving in range(lbfgs.HALVINGS):
                step_to(x, d, t, trial)
                phi_new = self.objective(trial, y, alive, self._g_new, True)
                if phi_new <= phi + lbfgs.ARMIJO * t * slope:
                    break
                t *= 0.5
            x[...] = trial
            g[...] = self._g_new
            phi = phi_new
        m = self.model
        edge_multipliers(x, m.edges, m.rest_length, self.k_edge, alive, substep * substep,
                         self.lambdas)


def simulation(cells: int, substeps: int, iterations: int) -> Simulation:
    matrices._kept.clear()
    return Simulation(clipped_fabric_scene(cells, {
        "behavior.solver": "lbfgs", "behavior.substeps": substeps,
        "behavior.iterations": iterations, "behavior.adaptive": False}))


def put_after_solve(sim: Simulation, stage) -> None:
    effects = sim.step.effects
    effects.insert(effects.index(sim.step.solver.projection) + 1, stage)


def put_in_place_of_solve(sim: Simulation, stage) -> None:
    effects = sim.step.effects
    effects[effects.index(sim.step.solver.projection)] = stage


def run(sim: Simulation) -> tuple[np.ndarray, float]:
    t0 = time.perf_counter()
    for _ in range(FRAMES):
        sim.advance_frame()
    return sim.state.x.copy(), 1e3 * (time.perf_counter() - t0) / FRAMES


def gap_rows(cells: int):
    converged, _ = run(simulation(cells, 1, 300))

    def row(label, sim):
        x, ms = run(sim)
        gap = float(np.linalg.norm(x - converged, axis=1).max())
        print(f"  {label:<40} {ms:8.1f} ms  {1e3 * gap:7.1f} mm  ({gap * cells:5.1f} edges)",
              flush=True)

    print(f"{cells} cells, 1 substep a frame, after {FRAMES} frames: ms a frame, the largest "
          "distance from the converged run")
    for iterations in (2, 4, 8):
        row(f"lbfgs, {iterations} iterations", simulation(cells, 1, iterations))
    plain = matrices.stiffness_matrix
    for beta in (0.3, 0.1):
        matrices.stiffness_matrix = lambda m, k, ks, beta=beta: plain(m, beta * k, ks)
        try:
            for iterations in (2, 8):
                row(f"lbfgs, P's edges x {beta}, {iterations} iterations",
                    simulation(cells, 1, iterations))
        finally:
            matrices.stiffness_matrix = plain
    for iterations, sweeps in ((2, 1), (2, 2), (4, 1)):
        sim = simulation(cells, 1, iterations)
        put_after_solve(sim, VertexSweeps(sim.step.solver.projection, sweeps))
        row(f"lbfgs {iterations} iterations + {sweeps} vertex sweep(s)", sim)
    if cells <= 32:
        for iterations in (1, 2, 5, 10):
            sim = simulation(cells, 1, iterations)
            old = sim.step.solver.projection
            newton = NewtonStep(old.model, iterations, 0.0, old.step_share)
            put_in_place_of_solve(sim, newton)
            row(f"Newton, {iterations} iterations", sim)


def reading_rows(sizes=(32, 64, 128, 256)):
    print("the worst of 30 frames' readings at 2 iterations: last move / shortest rest, "
          "edge-vector change / rest")
    for substeps in (1, 2, 4):
        for cells in sizes:
            if cells * substeps > 512:
                continue
            sim = simulation(cells, substeps, 2)
            m, solve = sim.model, sim.step.solver.projection
            move = change = 0.0
            for _ in range(FRAMES):
                sim.advance_frame()
                d = solve._last_step
                move = max(move, float(np.sqrt((d * d).sum(1)).max() / m.rest_length.min()))
                de = d[m.edges[:, 1]] - d[m.edges[:, 0]]
                change = max(change, float((np.sqrt((de * de).sum(1)) / m.rest_length).max()))
            print(f"  {substeps} substep(s), {cells:3d} cells: {move:.3f}  {change:.3f}",
                  flush=True)


if __name__ == "__main__":
    for cells in map(int, sys.argv[1:] or ["32", "64"]):
        gap_rows(cells)
    reading_rows()
