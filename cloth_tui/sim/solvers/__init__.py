"""The solvers, one folder each (xpbd/, pbd/, hpbd/, springs/, lbfgs/), found through one
registry (registry.py, reading cloth_tui/solver_specs.py). A solver is a SolverSpec (name and
traits, in solver_specs.py) and a SolverBase subclass (its stages and what the runner asks of
it): base.py."""

from .base import SolverBase, SolverSpec
from .registry import DEFAULT, names, register, spec, unregister

__all__ = ["DEFAULT", "SolverBase", "SolverSpec", "names", "register", "spec", "unregister"]
