"""A strip pulled along its length until it tears, shared by the tearing tests and the
solvers' tests, and the time of a run's first tear."""

from cloth_tui.scene import Scene
from cloth_tui.sim.run.runner import Simulation

STRETCH = 500.0    # N/m, the strip's stretch modulus
STRENGTH = 50.0    # N/m: it breaks at a strain of STRENGTH/STRETCH = 10 %
SPEED = 0.2        # m/s the far end is pulled at: 10 % of the 1 m strip at 0.5 s
FRAME = 1.0 / 60


def pulled_strip(adaptive: bool, substeps: int, pull_to: float | None = None,
                 **material) -> Scene:
    """A 0.25 × 1 m strip, no gravity, held along its near end, its far end pulled along
    the strip at SPEED (to `pull_to` m and held there, or on and on)."""
    end = 10.0 if pull_to is None else pull_to / SPEED
    return Scene().with_values({
        "cloth.size": [0.25, 1.0], "cloth.resolution": [9, 33], "cloth.pinned": "none",
        "cloth.height": 1.0, "scene.floor": False, "forces.gravity": False,
        "behavior.solver": "xpbd", "behavior.tear": True, "behavior.adaptive": adaptive,
        "behavior.substeps": substeps,
        "material": {"areal_density": 0.2, "stretch": STRETCH, "shear": 10.0,
                     "bending": 0.0, "tear_strength": STRENGTH, **material},
        "pins": [{"rows": [0, 0], "cols": [0, -1]},
                 {"rows": [-1, -1], "cols": [0, -1],
                  "keys": [[0.0, 0, 0, 0], [end, 0, 0, end * SPEED]]}]})


def first_tear(sim: Simulation, frames: int, torn_before: int = 0) -> float | None:
    """Run; the time of the frame in which the first (further) edge broke."""
    at = None
    for _ in range(frames):
        sim.advance_frame()
        if at is None and sim.state.torn > torn_before:
            at = sim.state.t
    return at
