"""The guard sees a position-based sheet that runs away while finite (issue 40: a fabric
without structural edges at one iteration, 151² in free fall, spread to kilometres across
with `finite` true, and nothing stopped it), and lets a load's spread stand."""

import numpy as np
import pytest

from cloth_tui.scene import Scene
from cloth_tui.sim.run.guard import RUNAWAY_SPREAD
from cloth_tui.sim.run.measures import grid_spread
from cloth_tui.sim.run.runner import Simulation


def falling_fabric_without_structure(solver: str) -> Scene:
    return Scene().with_values({
        "cloth.resolution": 151, "cloth.pinned": "none", "scene.floor": False,
        "behavior.structural": False, "behavior.iterations": 1, "behavior.solver": solver,
        "material": {"preset": "wang2011-royal-target"}})


@pytest.mark.parametrize("solver", ["xpbd", "hpbd"])
def test_a_sheet_that_runs_away_while_finite_is_retried_with_more_substeps(solver):
    sim = Simulation(falling_fabric_without_structure(solver))
    for _ in range(40):
        sim.advance_frame()
    st = sim.stats()
    x = sim.state.x
    # unguarded, the sheet spreads from frame ~13 to ~10 km across by frame 40 at 4 substeps
    assert st.recoveries >= 1 and sim.step.substeps > 4 and st.halted is None
    assert grid_spread(sim.model, x) < 1.5 and np.ptp(x[:, 0]) < 1.1


def test_the_spread_measure_sees_neighbours_apart_along_rows_and_columns():
    sim = Simulation(Scene().with_values({"cloth.resolution": 5}))
    m, x = sim.model, sim.state.x.copy()
    assert grid_spread(m, x) == pytest.approx(1.0)
    x[m.nx * 2 + 4, 1] -= 2 * RUNAWAY_SPREAD * m.spacing_x  # the last column, a middle row
    assert grid_spread(m, x) > 2 * RUNAWAY_SPREAD
    x = sim.state.x.copy()
    x[m.nx * 4 + 1, 2] += 3 * m.spacing_z  # the last row, away from the row above it
    assert grid_spread(m, x) == pytest.approx(4.0)
    x[0, 0] = np.nan
    assert np.isnan(grid_spread(m, x))


def test_a_sheet_pulled_apart_by_its_pins_is_a_load_not_a_divergence():
    """Nothing joins the particles of a sheet without structural, shear or bending
    constraints: pins that fly apart spread it far beyond RUNAWAY_SPREAD, and that spread
    stays at twice the substeps, so the frame stands."""
    scene = Scene().with_values({
        "cloth.resolution": 5, "cloth.pinned": "none", "scene.floor": False,
        "forces.gravity": False, "behavior.solver": "xpbd", "behavior.structural": False,
        "behavior.shear": False, "behavior.bending": False, "behavior.tethers": False})
    sim = Simulation(scene)
    sim.state.v[:] = 0.0
    sim.state.v[0] = (-40.0, 0.0, 0.0)  # 40 m/s: 10 cells a frame at 60 Hz
    for _ in range(10):
        sim.advance_frame()
    st = sim.stats()
    assert grid_spread(sim.model, sim.state.x) > RUNAWAY_SPREAD
    assert st.halted is None and st.recoveries == 0
