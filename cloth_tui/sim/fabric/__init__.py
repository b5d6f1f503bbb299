"""An SI material turned into the sheet's constraints: compliance per edge, shear cells,
bending stencils, tension curves."""
