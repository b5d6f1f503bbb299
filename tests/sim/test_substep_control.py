"""The substep controller alone: raise on excess, stop at the cap, lower with hysteresis."""

from cloth_tui.sim.substep_control import MAX_RAISE, SLACK_FRAMES, SubstepController


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
