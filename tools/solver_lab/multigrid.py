"""lbfgs's V-cycle (cloth_tui/sim/solvers/lbfgs/multigrid.py) beside the sparse LU factor it
replaced, on the fabric bench's denim sheet (issue 37).

    OPENBLAS_NUM_THREADS=1 python tools/solver_lab/multigrid.py [CELLS ...]

Per size: ms to apply each to three right-hand sides (the best of 10 blocks), ms to
make each at a new substep length, and the V-cycle's distance from P⁻¹ (relative, 2-norm)
on a random load. The V-cycle is the one the solver makes (without the bending stencils
where they are small: step_matrix.preconditioner_stiffness), P the full one. The factor is
SciPy's SuperLU in single precision with a minimum-degree
ordering of AᵀA + A, as lbfgs had it. docs/benchmarks.md (read by hand) has what this printed.
"""

from __future__ import annotations

import sys
import time

import numpy as np
from scipy.sparse.linalg import splu

from cloth_tui.bench.fabric_cost import clipped_fabric_scene
from cloth_tui.bench.timing import time_calls
from cloth_tui.sim.run.runner import Simulation
from cloth_tui.sim.solvers.lbfgs.multigrid import StepMultigrid
from cloth_tui.sim.solvers.lbfgs.step_matrix import preconditioner_stiffness, step_matrix

H = 1.0 / 120


def best_ms(apply) -> float:
    """The fastest of 10 blocks' ms a call (cloth_tui.bench.timing)."""
    return 1e3 * time_calls(apply, blocks=10, block_s=0.05).min_s


def once_ms(make) -> float:
    t0 = time.perf_counter()
    make()
    return 1e3 * (time.perf_counter() - t0)


def compare(cells: int) -> None:
    sim = Simulation(clipped_fabric_scene(cells, {"behavior.solver": "lbfgs"}))
    m, solve = sim.model, sim.step.solver.projection
    held = m.inv_mass == 0
    cycle = StepMultigrid(preconditioner_stiffness(m, solve.k_edge, solve.k_sten), m.mass,
                          held, m.nx, m.nz)
    matrix = step_matrix(m, solve.k_edge, solve.k_sten, H).tocsc().astype(np.float32)
    lu = splu(matrix, permc_spec="MMD_AT_PLUS_A", options={"SymmetricMode": True})
    b = np.random.default_rng(1).standard_normal((m.num_particles, 3))
    b[held] = 0.0
    cycle.set_step(H)
    exact = lu.solve(b.astype(np.float32)).astype(np.float64)
    error = np.linalg.norm(cycle.solve(b) - exact) / np.linalg.norm(exact)
    apply_cycle = best_ms(lambda: cycle.solve(b))
    apply_lu = best_ms(lambda: lu.solve(b.astype(np.float32)))
    remake_cycle = once_ms(lambda: cycle.set_step(H / 2))
    remake_lu = once_ms(lambda: splu(step_matrix(m, solve.k_edge, solve.k_sten, H / 2)
                                     .tocsc().astype(np.float32),
                                     permc_spec="MMD_AT_PLUS_A",
                                     options={"SymmetricMode": True}))
    print(f"{cells:4d} cells: apply V-cycle {apply_cycle:6.2f} ms, LU {apply_lu:6.2f} ms; "
          f"new h: V-cycle {remake_cycle:6.1f} ms, LU {remake_lu:7.1f} ms; "
          f"V-cycle from P⁻¹ {error:.3f} ({cycle.grids} grids)", flush=True)


if __name__ == "__main__":
    for n in [int(a) for a in sys.argv[1:]] or [64, 128, 256]:
        compare(n)
