"""The one list of solvers. The scene's `behavior.solver` choices, material validation, the
lab, the runner, the bench and the docs read it rather than naming solvers (the catenary lab
test and the bench's serial peer name pbd, whose rigid constraints they measure; the
work-precision study's reference is the springs' RK4). Adding one: a folder beside these with
its SolverSpec, and one line below (or `register` at run time, as a test's toy solver does)."""

from __future__ import annotations

from . import hpbd, lbfgs, pbd, springs, xpbd
from .base import SolverSpec

DEFAULT = "hpbd"  # behavior.solver's default

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


for _spec in (pbd.SPEC, hpbd.SPEC, xpbd.SPEC, springs.SPEC, lbfgs.SPEC):
    register(_spec)
