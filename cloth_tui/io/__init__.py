"""Bake and export: the simulation's motion written to files other tools read (USD through
Pixar's usd-core, OBJ/PLY sequences), and bakes read back. No UI imports."""
