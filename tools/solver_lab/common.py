"""Shared pieces of the solver lab (prototypes, not shipped): the clipped denim sheet of
issue 37 and the fabric's energy on the grid, for the candidates to be measured on."""

from __future__ import annotations

import numpy as np

from cloth_tui.scene import Scene
from cloth_tui.sim.runner import Simulation


def clipped_sheet(cells: int, preset: str = "denim", solver: str = "xpbd", substeps: int = 4,
                  iterations: int = 4, adaptive: bool = False, damping: float = 5.0) -> Scene:
    """tests/sim/test_fabric_resolution.py's sheet: 1 m, two clips of 1/16 m on one edge."""
    clip = max(1, cells // 16)
    return Scene().with_values({
        "cloth.size": 1.0, "cloth.resolution": cells + 1, "cloth.pinned": "none",
        "cloth.height": 1.0, "scene.floor": False, "behavior.solver": solver,
        "behavior.adaptive": adaptive, "behavior.substeps": substeps,
        "behavior.iterations": iterations,
        "material": {"preset": preset, "damping": damping},
        "pins": [{"rows": [0, 0], "cols": [0, clip]},
                 {"rows": [0, 0], "cols": [-1 - clip, -1]}]})


def centre_height(sim) -> float:
    m = sim.model
    x = sim.state.x.reshape(m.nz, m.nx, 3)
    rows, cols = sorted({(m.nz - 1) // 2, m.nz // 2}), sorted({(m.nx - 1) // 2, m.nx // 2})
    return float(x[np.ix_(rows, cols)][..., 1].mean())


def simulation(cells: int, **kw) -> Simulation:
    return Simulation(clipped_sheet(cells, **kw))
