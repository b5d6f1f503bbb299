"""xpbd: compliant position-based dynamics (Macklin et al. 2016), the solver of a material."""

from ..base import SolverSpec


def _load():
    from .solver import XPBDSolver
    return XPBDSolver


SPEC = SolverSpec(
    name="xpbd", summary="xpbd (compliant)", load=_load, takes_material=True, reference=True)
