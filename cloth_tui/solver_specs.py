"""The one list of solvers, as the scene, the lab, the bench and the docs know them: each
solver's name and traits (a `SolverSpec`), light enough for the scene schema and `--help` to
read without importing the physics. The simulation reads the same list
(sim/solvers/registry.py) and loads a solver's class, from its folder under sim/solvers/,
only when a step is built.

Callers read these traits rather than naming solvers (the catenary lab test and the bench's
serial peer name pbd, whose rigid constraints they measure; the work-precision study's
reference is the springs' RK4). Adding a solver: its folder under sim/solvers/ (its
SolverBase subclass and kernels) and its spec below (or `register` at run time, as a test's
toy solver does)."""

from __future__ import annotations

import importlib
from dataclasses import dataclass
from typing import TYPE_CHECKING, Callable

if TYPE_CHECKING:
    from .sim.solvers.base import SolverBase

DEFAULT = "hpbd"  # behavior.solver's default


@dataclass(frozen=True)
class SolverSpec:
    """A solver as the scene, the lab, the bench and the docs know it.

    `load` returns the solver's class (importing its kernels only then). `takes_material`:
    its constraints take a compliance each, so it can run a [material]. `solves_constraints`:
    it projects constraints one at a time, in passes over the sheet (pbd, xpbd, hpbd: the
    solvers the work-precision study sets beside the springs' integrators). What the
    accuracy control bounds is each solver's own (SolverBase.solve_error).
    `tethers`: it may add long-range attachments where pins exist (position-based solvers;
    projected positions an integrator keeps moving would add energy). `integrators`: the
    time integrators it runs, the first being what behavior.integrator = "auto" means.
    `reference`: the plain solve of a material's implicit step, with no acceleration, that
    the lab's results are stated for and faster solvers are measured against (one solver)."""
    name: str
    summary: str
    load: Callable[[], type[SolverBase]]
    takes_material: bool = False
    solves_constraints: bool = True
    tethers: bool = True
    integrators: tuple[str, ...] = ("verlet",)
    reference: bool = False

    def solver_class(self) -> type[SolverBase]:
        return self.load()


def _in_folder(module: str, name: str) -> Callable[[], type[SolverBase]]:
    """A `load` that imports class `name` from cloth_tui.sim.solvers.<module> when called."""
    def load():
        return getattr(importlib.import_module(f"cloth_tui.sim.solvers.{module}"), name)
    return load


_SPECS: dict[str, SolverSpec] = {}


def register(spec: SolverSpec) -> None:
    """Offer `spec`'s solver by its name (a name already taken is refused)."""
    if spec.name in _SPECS:
        raise ValueError(f"a solver named {spec.name!r} is registered already")
    _SPECS[spec.name] = spec


def unregister(name: str) -> None:
    """Withdraw a solver `register` added (a test's toy solver)."""
    del _SPECS[name]


def names(*, takes_material: bool | None = None, solves_constraints: bool | None = None,
          reference_first: bool = False) -> tuple[str, ...]:
    """The registered solvers' names in registration order, or those whose spec's
    `takes_material` and `solves_constraints` are as given (None: either);
    `reference_first` puts the reference solver (SolverSpec.reference) first, as the
    lab's default."""
    picked = [n for n, s in _SPECS.items()
              if takes_material in (None, s.takes_material)
              and solves_constraints in (None, s.solves_constraints)]
    if reference_first:
        picked.sort(key=lambda n: not _SPECS[n].reference)
    return tuple(picked)


def spec(name: str) -> SolverSpec:
    """The registered solver `name`; KeyError if there is none (the scene's choices have
    refused unknown names before anything asks)."""
    return _SPECS[name]


def integrator_for(behavior) -> str:
    """The integrator behavior.solver runs: behavior.integrator, or for `auto` the first
    its spec names (verlet for the position-based solvers; implicit_euler, stable at any
    substep length, for springs)."""
    if behavior.integrator != "auto":
        return behavior.integrator
    return spec(behavior.solver).integrators[0]


def auto_integrators() -> str:
    """"verlet for hpbd/pbd/xpbd, implicit_euler for springs": what behavior.integrator =
    "auto" means, by solver."""
    by_integrator: dict[str, list[str]] = {}
    for n in names():
        by_integrator.setdefault(spec(n).integrators[0], []).append(n)
    return ", ".join(f"{i} for {'/'.join(ns)}" for i, ns in by_integrator.items())


def reference() -> str:
    """The reference solver's name (SolverSpec.reference)."""
    return next(n for n, s in _SPECS.items() if s.reference)


class Names:
    """The registered names (or those `names` picks by its keywords) as a live
    sequence, for a key's or a command's choices: a solver registered later is one too."""

    def __init__(self, **picks):
        self._picks = picks  # names()' keywords

    def _names(self) -> tuple[str, ...]:
        return names(**self._picks)

    def __iter__(self):
        return iter(self._names())

    def __len__(self) -> int:
        return len(self._names())

    def __contains__(self, name) -> bool:
        return name in self._names()

    def __getitem__(self, i):
        return self._names()[i]

    def __repr__(self) -> str:
        return repr(self._names())


register(SolverSpec(
    name="pbd", summary="pbd (the original's Gauss-Seidel position projection)",
    load=_in_folder("pbd.solver", "PBDSolver")))
register(SolverSpec(
    name="hpbd",
    summary="hpbd (pbd with coarse levels: the accuracy at a cost that grows with the sheet, "
            "not its cube)",
    load=_in_folder("hpbd.solver", "HPBDSolver"), takes_material=True))
register(SolverSpec(
    name="xpbd", summary="xpbd (compliant)", load=_in_folder("xpbd.solver", "XPBDSolver"),
    takes_material=True, reference=True))
register(SolverSpec(
    name="springs", summary="springs (Hooke)", load=_in_folder("springs.solver", "SpringSolver"),
    solves_constraints=False, tethers=False,
    # implicit_euler first: what "auto" means, the one stable at any substep for stiff springs
    integrators=("implicit_euler", "verlet", "explicit_euler", "symplectic_euler", "midpoint",
                 "rk4")))
register(SolverSpec(
    name="lbfgs",
    summary="lbfgs (a material's implicit step by quasi-Newton from a constant matrix's "
            "multigrid cycle: a fabric's equilibrium at a cost that grows with the sheet)",
    load=_in_folder("lbfgs.solver", "LBFGSSolver"), takes_material=True,
    solves_constraints=False, tethers=False, integrators=("implicit_euler", "bdf2")))
