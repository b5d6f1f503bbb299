"""pbd: the original's Gauss-Seidel position projection (XPBD with compliance 0)."""

from ..base import SolverSpec


def _load():
    from .solver import PBDSolver
    return PBDSolver


SPEC = SolverSpec(
    name="pbd", summary="pbd (the original's Gauss-Seidel position projection)", load=_load)
