"""springs: Hooke springs, force-based, advanced by a chosen time integrator.
Its spec (name and traits) is declared in cloth_tui/solver_specs.py."""
