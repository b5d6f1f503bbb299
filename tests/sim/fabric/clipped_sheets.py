"""A 1 m denim sheet held by two clips 1/16 m long at the corners of one edge, shared by
the resolution tests and the solvers' tests, where its centre hangs, and denim's numbers
typed out."""

import numpy as np

from cloth_tui.scene import Scene

PRESET = "denim"
# denim's numbers typed out (a typed stretch is linear, where the preset stiffens with
# strain), so solvers compared on it minimise one energy
TYPED_DENIM = {"areal_density": 0.324, "stretch": [410.7, 2027.8], "shear": 26.69,
               "bending": 1.605e-5, "damping": 5.0}


def clipped_sheet(cells: int, substeps: int, iterations: int) -> Scene:
    clip = cells // 16  # cells of edge each clip holds
    return Scene().with_values({
        "cloth.size": 1.0, "cloth.resolution": cells + 1, "cloth.pinned": "none",
        "cloth.height": 1.0, "scene.floor": False, "behavior.solver": "xpbd",
        "behavior.adaptive": False, "behavior.substeps": substeps,
        "behavior.iterations": iterations,
        "material": {"preset": PRESET, "damping": 5.0},
        "pins": [{"rows": [0, 0], "cols": [0, clip]},
                 {"rows": [0, 0], "cols": [-1 - clip, -1]}]})


def centre_height(sim) -> float:
    """y of the sheet's centre (between the middle particles on an even grid)."""
    m = sim.model
    x = sim.state.x.reshape(m.nz, m.nx, 3)
    rows, cols = sorted({(m.nz - 1) // 2, m.nz // 2}), sorted({(m.nx - 1) // 2, m.nx // 2})
    return float(x[np.ix_(rows, cols)][..., 1].mean())
