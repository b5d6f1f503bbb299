"""The springs guard's energy check judges the step's own growth: a contact pushing a sheet
out of an object's skin is a source of energy, not divergence (issue 40: a sheet at rest in
the floor's skin with gravity off halted "diverges even at 64 substeps", its push growing as
the guard's retries shortened h)."""

import pytest

from cloth_tui.sim.run.runner import Simulation

from ..helpers import run, scene


@pytest.mark.parametrize("integrator", ["implicit_euler", "rk4"])
@pytest.mark.parametrize("height", [-0.498, -0.51])  # in the floor's 5 mm skin, and below it
def test_a_sheet_pushed_out_of_the_floor_without_gravity_is_not_a_divergence(integrator,
                                                                              height):
    sim = run(Simulation(scene(behavior__solver="springs", behavior__integrator=integrator,
                               forces__gravity=False, cloth__height=height,
                               cloth__pinned="none", cloth__resolution=12)), 10)
    st = sim.stats()
    assert st.halted is None and st.recoveries == 0 and st.finite, st.halted
    assert st.min_y >= -0.5 + 0.005 - 1e-9  # out of the floor and its skin

