"""The solvers' one list, as the simulation reads it: the specs are declared in
cloth_tui/solver_specs.py, where the scene schema reads them without importing the physics;
a spec's `load` gives the class in its folder here."""

from __future__ import annotations

from ...solver_specs import (DEFAULT, Names, SolverSpec, integrator_for, names, reference,
                             register, spec, unregister)

__all__ = ["DEFAULT", "Names", "SolverSpec", "integrator_for", "names", "reference",
           "register", "spec", "unregister"]
