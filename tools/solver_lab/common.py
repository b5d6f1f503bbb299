"""Shared pieces of the solver lab (prototypes, not shipped): the clipped denim sheet of
issue 37 and the fabric's energy on the grid, for the candidates to be measured on."""

from __future__ import annotations

import numpy as np

from cloth_tui.scene import Scene
from cloth_tui.sim.run.runner import Simulation

# The fabrics measured here with their numbers typed out (a typed stretch is linear, so every
# solver minimises the same energy): the presets' zero-strain values.
LINEAR = {
    "denim": {"areal_density": 0.324, "stretch": [410.7, 2027.8], "shear": 26.69,
              "bending": 1.605e-5},
    "cotton": {"areal_density": 0.120, "stretch": [1000.0, 800.0], "shear": 50.0,
               "bending": 1.0e-5},
    "tablecloth": {"areal_density": 0.128, "stretch": [4004.2, 4055.0], "shear": 9.59,
                   "bending": 1.293e-5},
    "jersey": {"areal_density": 0.187, "stretch": [33.19, 68.95], "shear": 18.43,
               "bending": 5.80e-6},
}


def clipped_sheet(cells: int, preset: str = "denim", solver: str = "xpbd", substeps: int = 4,
                  iterations: int = 4, adaptive: bool = False, damping: float = 5.0) -> Scene:
    """tests/sim/fabric/test_fabric_resolution.py's sheet: 1 m, two clips of 1/16 m on one edge."""
    clip = max(1, cells // 16)
    return Scene().with_values({
        "cloth.size": 1.0, "cloth.resolution": cells + 1, "cloth.pinned": "none",
        "cloth.height": 1.0, "scene.floor": False, "behavior.solver": solver,
        "behavior.adaptive": adaptive, "behavior.substeps": substeps,
        "behavior.iterations": iterations,
        "material": {**LINEAR[preset], "damping": damping},
        "pins": [{"rows": [0, 0], "cols": [0, clip]},
                 {"rows": [0, 0], "cols": [-1 - clip, -1]}]})


def centre_height(sim) -> float:
    m = sim.model
    x = sim.state.x.reshape(m.nz, m.nx, 3)
    rows, cols = sorted({(m.nz - 1) // 2, m.nz // 2}), sorted({(m.nx - 1) // 2, m.nx // 2})
    return float(x[np.ix_(rows, cols)][..., 1].mean())


def simulation(cells: int, **kw) -> Simulation:
    return Simulation(clipped_sheet(cells, **kw))
