"""lbfgs: a material's implicit step solved as a minimisation, by L-BFGS whose first guess of
the inverse Hessian is a constant matrix's (projective dynamics' matrix, Liu, Bouaziz &
Kavan 2017), applied by one multigrid V-cycle on the sheet's grid: the sheet's
low-frequency error goes in one cycle, at a cost of a few passes over the matrix.
Its spec (name and traits) is declared in cloth_tui/solver_specs.py."""
