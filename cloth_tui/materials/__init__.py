"""Fabrics in SI units: the measured-fabric table (presets.toml, presets.py) and the
`[material]` section's keys and validation (schema.py). Pure Python: no numpy, so the scene
loader can use it and `cloth-tui --help` stays fast. The discretisation of a material on a
grid is cloth_tui.sim.fabric.material."""
