"""Numerical damping: the energy a run loses that no damping key asked for, reported, and
bounded by behavior.energy_tolerance through the adaptive substeps."""

import pytest

from cloth_tui.sim.run.runner import Simulation

from ..helpers import scene

SWING = dict(behavior__damping=0.0, cloth__pinned="one_edge", cloth__resolution=12,
             scene__floor=False)


def swing(frames: int = 120, **overrides):
    """An undamped sheet released flat, held along one edge, swinging for `frames` frames:
    (share of its free energy lost, the substeps of every frame, the simulation). The end's
    free energy is the mean over the next 10 frames: the last substep's velocities misread
    the kinetic energy of one frame by a few per cent either way."""
    sim = Simulation(scene(**{**SWING, **overrides}))
    start = sim.free_energy()
    substeps = []
    for _ in range(frames):
        sim.advance_frame()
        substeps.append(sim.step.substeps)
    end = []
    for _ in range(10):
        sim.advance_frame()
        end.append(sim.free_energy())
    return 1.0 - sum(end) / len(end) / start, substeps, sim


# denim's damping is 0: nothing but the step takes the swing's energy
@pytest.mark.parametrize("solver, material", [("pbd", None), ("xpbd", None),
                                              ("xpbd", {"preset": "denim"})])
def test_an_energy_tolerance_of_10_percent_over_2_s_keeps_a_swing_within_it(solver, material):
    # 4 fixed substeps lose a third of the swing in 2 s (denim: 40 %); 0.05/s (10 % over
    # 2 s) makes the control take what it needs
    fabric = {} if material is None else {"material": material}
    fixed, _, sim = swing(behavior__solver=solver, behavior__adaptive=False,
                          behavior__energy_tolerance=0.05, **fabric)
    assert fixed > 0.2  # without adaptive the tolerance is reported, not met
    assert sim.numerical_damping > 0.05 and sim.stats().tolerance_met is False
    lost, substeps, sim = swing(behavior__solver=solver, behavior__energy_tolerance=0.05,
                                **fabric)
    assert abs(lost) <= 0.10, (lost, substeps)
    mean = sum(substeps) / len(substeps)
    assert 4 * 4 < mean <= 128, mean  # the work it took, reported per frame
    st = sim.stats()
    assert st.energy_tolerance == 0.05 and st.substeps_used == sim.step.substeps


def test_the_damping_a_key_asks_for_is_not_numerical():
    # behavior.damping = 3 % per 18 ms takes nearly all of the swing; at 64 substeps that
    # is the key's loss, not the step's
    lost, _, sim = swing(behavior__damping=0.03, behavior__substeps=64,
                         behavior__adaptive=False)
    assert lost > 0.9
    assert abs(sim.numerical_damping) < 0.02
    lost, _, sim = swing(behavior__substeps=64, behavior__adaptive=False)
    assert lost < 0.1 and abs(sim.numerical_damping) < 0.02


def test_a_materials_damping_is_not_numerical_and_replaces_behavior_damping():
    # denim with a decay rate of 3/s takes nearly all of the swing; behavior.damping (3 %
    # per 18 ms, which would take as much) is not the material's and asks for nothing
    lost, _, sim = swing(behavior__solver="xpbd", material={"preset": "denim", "damping": 3.0},
                         behavior__damping=0.03, behavior__substeps=64,
                         behavior__adaptive=False)
    assert lost > 0.9
    assert abs(sim.numerical_damping) < 0.02


def test_numerical_damping_is_none_where_energy_comes_in_or_goes_out_by_contact():
    assert swing(30, forces__wind=True)[2].stats().numerical_damping is None
    # a free sheet lying on the floor: every frame touches it (friction and contacts)
    on_floor = Simulation(scene(cloth__pinned="none", cloth__height=0.01))
    for _ in range(30):
        on_floor.advance_frame()
    assert on_floor.stats().numerical_damping is None


def test_simulate_json_and_stats_report_error_stretch_and_numerical_damping_apart():
    lost, _, sim = swing(30)
    st = sim.stats()
    for k in ("error", "max_stretch", "numerical_damping", "error_tolerance",
              "energy_tolerance", "solver"):
        assert k in st.as_dict(), k
    assert st.error == pytest.approx(st.max_stretch)  # pbd: the error is the stretch
    assert st.energy_tolerance is None  # 0: unbounded


def test_the_meter_measures_from_where_the_last_frame_ended_and_forgets_jumps():
    from cloth_tui.sim.run.numerical_damping import AVERAGE_FRAMES, DampingMeter
    meter = DampingMeter()
    calls = []
    start = meter.begin(True, lambda: calls.append(1) or 10.0)
    assert start == 10.0 and calls == [1]
    # lost 1 J of which 0.5 J asked for, of 5 J free, in 0.1 s: 1/s
    assert meter.end(start, 9.0, 0.5, 5.0, 0.1) == pytest.approx(1.0)
    assert meter.begin(True, lambda: 99.0) == 9.0  # the next frame starts where it ended
    meter.report(halted=False)
    assert meter.average == pytest.approx(1.0)
    meter.end(9.0, 9.0, 0.0, 5.0, 0.1)  # a frame that lost nothing moves the mean a little
    meter.report(halted=False)
    assert meter.average == pytest.approx(1.0 - 1.0 / AVERAGE_FRAMES)
    meter.forget()  # a push: the next frame's start is measured afresh
    assert meter.begin(True, lambda: 3.0) == 3.0
    assert meter.begin(False, lambda: 3.0) is None
    meter.unmeasured()
    meter.report(halted=False)
    assert meter.frame is None and meter.average is None
