"""pbd: the original's Gauss-Seidel position projection (XPBD with compliance 0).
Its spec (name and traits) is declared in cloth_tui/solver_specs.py."""
