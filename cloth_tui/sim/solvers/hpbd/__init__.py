"""hpbd: PBD with coarse levels (Müller 2008), or with a material XPBD whose edge
multipliers take coarse corrections: the accuracy at a cost that grows with the sheet.
Its spec (name and traits) is declared in cloth_tui/solver_specs.py."""
