"""The substep controller alone: raise on excess, stop at the cap, lower with hysteresis; the
solve error redoes a frame, the numerical damping raises the count for the frames after."""

from cloth_tui.sim.run.substep_control import (ENERGY_FRAMES, ENERGY_SAFETY, ENERGY_SLACK_FRAMES,
                                               MAX_RAISE, SLACK_FRAMES, SubstepController)


def test_a_frame_over_tolerance_is_redone_with_more_substeps_up_to_the_cap():
    c = SubstepController(tolerance=0.05, floor=4, cap=40)
    assert c.redo_with(0.04) is None  # met: accepted
    assert c.redo_with(0.2) == 10     # √(0.2/0.05) · 1.25 = 2.5× → 10
    assert c.redo_with(50.0) == 40    # at most ×4, and never past the cap
    assert c.redo_with(50.0) is None  # at the cap: accepted as it is
    c.accept(50.0)
    assert c.met is False


def test_one_wild_frame_cannot_jump_to_the_cap():
    c = SubstepController(tolerance=0.01, floor=2, cap=1000)
    assert c.redo_with(1e6) == 2 * MAX_RAISE


def test_slack_lowers_after_a_window_never_below_the_floor():
    c = SubstepController(tolerance=0.05, floor=4, cap=128, substeps=64)
    for _ in range(SLACK_FRAMES - 1):
        assert c.accept(0.001) == 64  # not before the window is full
    assert c.accept(0.001) == 32      # at most halved per window
    for _ in range(5 * SLACK_FRAMES):
        c.accept(0.001)
    assert c.substeps == 4


def test_lowering_aims_under_the_tolerance_so_the_count_does_not_oscillate():
    c = SubstepController(tolerance=0.05, floor=1, cap=128, substeps=10)
    for _ in range(SLACK_FRAMES):
        c.accept(0.035)  # ⌈10·√(0.035·1.25/0.05)⌉ = ⌈9.4⌉: at 9 it would pass τ/1.25
    assert c.substeps == 10
    for _ in range(SLACK_FRAMES):
        c.accept(0.01)  # ⌈10·√(0.01·1.25/0.05)⌉ = 5
    assert c.substeps == 5


def test_a_raise_restarts_the_slack_window():
    c = SubstepController(tolerance=0.05, floor=4, cap=128, substeps=16)
    for _ in range(SLACK_FRAMES - 1):
        c.accept(0.001)
    c.redo_with(0.06)
    c.accept(0.04)
    assert c.substeps > 16


def test_not_adaptive_reports_and_changes_nothing():
    c = SubstepController(tolerance=0.05, floor=4, cap=128, adaptive=False)
    assert c.redo_with(3.0) is None
    assert c.accept(3.0) == 4 and c.met is False


def test_cap_below_floor_means_the_floor():
    c = SubstepController(tolerance=0.05, floor=8, cap=2)
    assert c.cap == 8 and c.redo_with(1.0) is None


# --- numerical damping --------------------------------------------------------------------

def test_numerical_damping_over_its_tolerance_raises_the_next_frames_after_a_few_frames():
    c = SubstepController(tolerance=0.05, floor=4, cap=128, energy_tolerance=0.05)
    for _ in range(ENERGY_FRAMES - 1):
        assert c.accept(0.001, damping=0.2) == 4  # one frame's damping is no measure yet
    assert c.met is False  # the mean so far is over τ_E
    # the mean 0.2/s is 4× τ_E; aimed at τ_E/ENERGY_SAFETY that is 8×, at most ×4
    assert c.accept(0.001, damping=0.2) == 4 * MAX_RAISE
    assert c.mean_damping is None  # the count changed: a new mean starts


def test_the_mean_damping_decides_not_one_frame():
    c = SubstepController(tolerance=0.05, floor=4, cap=128, energy_tolerance=0.05)
    for k in range(4 * ENERGY_FRAMES):
        c.accept(0.001, damping=0.25 if k % 10 == 5 else 0.0)  # bursts 5× τ_E, mean ½ τ_E
    assert c.substeps == 4 and c.met


def test_damping_raise_factor_and_no_redo():
    c = SubstepController(tolerance=0.05, floor=10, cap=128, energy_tolerance=0.1)
    assert c.redo_with(0.001) is None  # the frame's error is met: energy never redoes
    for _ in range(ENERGY_FRAMES):
        c.accept(0.001, damping=0.12)
    assert c.substeps == round(10 * 0.12 * ENERGY_SAFETY / 0.1)  # ⌈24.0⌉


def test_with_an_energy_tolerance_lowering_waits_longer_and_keeps_damping_in_bounds():
    c = SubstepController(tolerance=0.05, floor=4, cap=128, substeps=64, energy_tolerance=0.05)
    for _ in range(SLACK_FRAMES):
        c.accept(0.0001, damping=0.001)
    assert c.substeps == 64  # a quiet half-second is not enough
    for _ in range(ENERGY_SLACK_FRAMES - SLACK_FRAMES):
        c.accept(0.0001, damping=0.02)
    # mean 0.0155/s... the window's: ⌈64·max(√(1e-4·1.25/0.05), 0.01525·2/0.05)⌉ = 40
    assert c.substeps == 40


def test_without_an_energy_tolerance_damping_is_only_reported():
    c = SubstepController(tolerance=0.05, floor=4, cap=128)
    for _ in range(3 * ENERGY_FRAMES):
        assert c.accept(0.001, damping=5.0) == 4
    assert c.met and c.mean_damping == 5.0


def test_a_tolerance_that_underflowed_to_zero_raises_to_the_cap_and_never_raises_an_error():
    # a tear strength of 5e-324 N/m gives a solve-error tolerance of 0: nothing but an exact
    # solve meets it, so the count goes to the cap, the frame is accepted there, unmet
    c = SubstepController(tolerance=0.0, floor=4, cap=64, energy_tolerance=0.0)
    while (n := c.redo_with(1e-3)) is not None:
        assert n <= 64
    assert c.substeps == 64
    for _ in range(ENERGY_SLACK_FRAMES + 1):
        assert c.accept(1e-3, damping=1e-3) == 64
    assert c.met is False
    assert SubstepController(tolerance=0.0, floor=4, cap=64).meets(0.0)  # an exact solve does


def test_a_burst_of_damping_after_a_quiet_while_raises_within_a_few_frames():
    # a swing's free edge whipping round: 0.3/s for a few frames after two quiet seconds
    c = SubstepController(tolerance=0.05, floor=4, cap=128, energy_tolerance=0.05)
    for _ in range(100):
        c.accept(0.001, damping=0.005)
    for k in range(ENERGY_FRAMES):
        c.accept(0.001, damping=0.3)
    assert c.substeps > 4


def test_a_bound_on_energy_made_alone_leaves_energy_lost_to_the_report():
    # lbfgs's default (the runner sets it from the solver): energy made is an error of the
    # solve at any tolerance; energy lost is what implicit Euler does
    c = SubstepController(tolerance=0.05, floor=2, cap=128, made_tolerance=0.25)
    for _ in range(3 * ENERGY_FRAMES):
        assert c.accept(0.001, damping=5.0) == 2
    assert c.met
    for _ in range(ENERGY_FRAMES):
        c.accept(0.001, damping=-0.2)  # under the bound
    assert c.substeps == 2
    for _ in range(ENERGY_FRAMES):
        c.accept(0.001, damping=-1.0)
    assert c.substeps > 2 and not c.met


def test_energy_made_is_bounded_as_energy_lost_is():
    c = SubstepController(tolerance=0.05, floor=4, cap=128, energy_tolerance=0.05)
    for _ in range(ENERGY_FRAMES):
        c.accept(0.001, damping=-0.2)
    assert c.substeps > 4 and not c.met


def test_a_burst_that_goes_on_after_a_raise_raises_again_at_once():
    c = SubstepController(tolerance=0.05, floor=4, cap=128, energy_tolerance=0.05)
    for _ in range(ENERGY_FRAMES):
        c.accept(0.001, damping=0.2)
    raised = c.substeps
    assert raised > 4
    # the frames before, as the raised count would have had them, are in the recent mean
    assert c.accept(0.001, damping=0.4) > raised


def test_frames_whose_damping_is_not_measured_leave_no_stale_burst_behind():
    # a drop whips round (raised to the cap), then lies on the floor, where contacts make
    # the damping unmeasurable: the count comes down and stays down
    c = SubstepController(tolerance=0.05, floor=1, cap=128, energy_tolerance=0.05)
    while c.substeps < c.cap:
        c.accept(0.0, damping=1.0)
    for _ in range(ENERGY_SLACK_FRAMES):
        c.accept(0.0, damping=None)
    assert c.substeps == 64
    for _ in range(ENERGY_FRAMES):
        assert c.accept(0.0, damping=None) == 64
