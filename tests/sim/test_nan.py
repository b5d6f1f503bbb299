"""A NaN that enters the state is seen, by every solver's path (issue 12 item 3).

Under numba's `fastmath=True` LLVM may assume no NaN: `math.isfinite(nan)` compiled to True
and comparisons with NaN folded, so a guard inside a kernel was dead code and a NaN could be
clamped into a plausible number. The kernels now use FASTMATH (jit.py), which keeps NaN."""

import math

import pytest
from numba import njit

from cloth_tui.scene import Scene
from cloth_tui.sim import pipeline
from cloth_tui.sim.jit import FASTMATH
from cloth_tui.sim.model import build_model
from cloth_tui.sim.run.runner import Simulation
from cloth_tui.sim.solvers.springs.integrators import ORDERS
from cloth_tui.sim.state import ClothState

PATHS = [("pbd", "verlet"), ("xpbd", "verlet")] + [("springs", i) for i in ORDERS]


def path_scene(solver, integrator):
    s = Scene().with_value("cloth.resolution", 8).with_value("behavior.solver", solver)
    s = s.with_value("behavior.integrator", integrator)
    if solver == "springs" and integrator != "implicit_euler":
        s = s.with_value("behavior.stiffness", 50.0)  # stable for the explicit ones
    return s


@njit(fastmath=FASTMATH)
def _isfinite(v):
    return math.isfinite(v)


def test_fastmath_flags_keep_nan_checks():
    assert not _isfinite(math.nan) and not _isfinite(math.inf) and _isfinite(1.0)


@pytest.mark.parametrize("solver,integrator", PATHS)
@pytest.mark.parametrize("where", ["x", "v"])
def test_nan_in_the_state_stays_visible_after_a_frame(solver, integrator, where):
    s = path_scene(solver, integrator)
    model = build_model(s.cloth, s.behavior)
    step, state = pipeline.build(s, model), ClothState.from_model(model)
    step.frame(state)
    getattr(state, where)[27, 1] = math.nan  # a free particle inside the sheet
    step.frame(state)
    assert not state.is_finite(), "a kernel hid the NaN"


@pytest.mark.parametrize("solver,integrator", PATHS)
def test_runner_recovers_from_an_injected_nan(solver, integrator):
    sim = Simulation(path_scene(solver, integrator))
    sim.advance_frame()
    sim.state.v[27, 1] = math.nan
    sim.advance_frame()
    assert sim.recoveries >= 1 and sim.state.is_finite() and not sim.halted


def test_implicit_euler_drops_a_non_finite_warm_start():
    """The CG solve starts from the last substep's Δv; a start that is not finite must be
    dropped (the `math.isfinite` guard), or every later solve is NaN too."""
    s = path_scene("springs", "implicit_euler")
    model = build_model(s.cloth, s.behavior)
    step, state = pipeline.build(s, model), ClothState.from_model(model)
    step.substep(state)
    step.solver.integrator.dv[27, 1] = math.nan
    step.substep(state)
    assert state.is_finite()
