"""lbfgs: a material's implicit step solved as a minimisation, by L-BFGS whose first guess of
the inverse Hessian is a prefactored constant matrix (projective dynamics' matrix, Liu,
Bouaziz & Kavan 2017): the sheet's low-frequency error goes in one direct solve, so the
cost of an accurate step grows with the sheet, not faster.
Its spec (name and traits) is declared in cloth_tui/solver_specs.py."""
