"""The implicit-Euler objective of a fabric step and its gradient for the lab's prototypes:
the registered lbfgs solver's own kernel (cloth_tui/sim/solvers/lbfgs/step_energy.py), with
the argument order the prototypes were written for."""

from __future__ import annotations

from cloth_tui.sim.solvers.lbfgs.step_energy import step_objective


def objective(x, y, mass_h2, inv_mass, edges, rest, k_edge, alive, cells, cell_alive, k_cell,
              scale, sp, sc, k_sten, sten_alive, grad, want_grad, theta):
    return step_objective(x, y, mass_h2, inv_mass, edges, rest, k_edge, alive, cells,
                          cell_alive, k_cell, scale, sp, sc, k_sten, sten_alive, theta, grad,
                          want_grad)
