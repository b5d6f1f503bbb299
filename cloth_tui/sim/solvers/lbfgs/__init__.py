"""lbfgs: a material's implicit step solved as a minimisation, by L-BFGS whose first guess of
the inverse Hessian is a prefactored constant matrix (projective dynamics' matrix, Liu,
Bouaziz & Kavan 2017): the sheet's low-frequency error goes in one direct solve, so the
cost of an accurate step grows with the sheet, not faster."""

from ..base import SolverSpec


def _load():
    from .solver import LBFGSSolver
    return LBFGSSolver


SPEC = SolverSpec(
    name="lbfgs",
    summary="lbfgs (a material's implicit step by quasi-Newton with a prefactored matrix: "
            "a fabric's equilibrium at a cost that grows with the sheet)",
    load=_load, takes_material=True, solves_constraints=False, tethers=False,
    integrators=("implicit_euler",))
