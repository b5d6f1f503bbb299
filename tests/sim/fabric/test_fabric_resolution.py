"""Resolution independence: a 1 m sheet of denim held by two clips at the corners of one
edge settles to the same centre sag at every grid, and at 10 and 40 substeps.

The clips are 1/16 m (6.25 cm) long, the length every grid here holds exactly: one cell of
the 16-cell grid, eight of the 128-cell one (a clip of 5 cm would hold 0 to 6.7 cm of edge
depending on the grid, and the sag with it). The drag (`damping`, 5/s) only takes the
motion out: it acts on velocities and changes no equilibrium. A settled sheet is checked
to be settled (its sag no longer moving) before it is compared."""

import pytest

from cloth_tui.sim.run.runner import Simulation

from .clipped_sheets import centre_height, clipped_sheet

SETTLE_S = 2.5  # s; settled by then at every grid here (the check below says so)
CHECK_S = 0.5  # over the last half second the sag may move by 0.3 % at most


def settled_sag(cells: int, substeps: int = 40, iterations: int = 5) -> float:
    sim = Simulation(clipped_sheet(cells, substeps, iterations))
    rate = sim.scene.behavior.frame_rate
    frames = int(SETTLE_S * rate)
    for f in range(frames):
        if f == frames - int(CHECK_S * rate):
            before = 1.0 - centre_height(sim)
        sim.advance_frame()
    sag = 1.0 - centre_height(sim)  # the clips hold the edge at y = 1 m
    assert abs(sag - before) < 3e-3 * sag, "not settled"
    assert sim.stats().finite
    return sag


@pytest.fixture(scope="module")
def sags():
    """The settled sag at 16, 32 and 64 cells a side, m."""
    return {cells: settled_sag(cells) for cells in (16, 32, 64)}


def spread(values) -> float:
    return max(values) / min(values) - 1.0


def test_the_centre_sag_is_the_same_at_16_32_and_64_cells(sags):
    assert all(0.3 < s < 0.7 for s in sags.values())  # hanging, not fallen or held flat
    assert spread(sags.values()) < 0.03


@pytest.mark.slow
def test_the_centre_sag_is_the_same_at_128_cells(sags):
    assert spread([*sags.values(), settled_sag(128)]) < 0.03


def test_the_centre_sag_is_the_same_at_10_and_40_substeps(sags):
    ten = settled_sag(32, substeps=10, iterations=10)
    assert abs(ten / sags[32] - 1.0) < 0.01
