"""hpbd: PBD with coarse levels (Müller 2008), or with a material XPBD whose edge
multipliers take coarse corrections: the accuracy at a cost that grows with the sheet."""

from ..base import SolverSpec


def _load():
    from .solver import HPBDSolver
    return HPBDSolver


SPEC = SolverSpec(
    name="hpbd",
    summary="hpbd (pbd with coarse levels: the accuracy at a cost that grows with the sheet, "
            "not its cube)",
    load=_load, takes_material=True)
