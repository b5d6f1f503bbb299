"""springs: Hooke springs, force-based, advanced by a chosen time integrator."""

from ..base import SolverSpec


def _load():
    from .solver import SpringSolver
    return SpringSolver


SPEC = SolverSpec(
    name="springs", summary="springs (Hooke)", load=_load, solves_constraints=False,
    tethers=False,
    # implicit_euler first: what "auto" means, the one stable at any substep for stiff springs
    integrators=("implicit_euler", "verlet", "explicit_euler", "symplectic_euler", "midpoint",
                 "rk4"))
