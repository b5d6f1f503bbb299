"""xpbd: compliant position-based dynamics (Macklin et al. 2016), the solver of a material.
Its spec (name and traits) is declared in cloth_tui/solver_specs.py."""
