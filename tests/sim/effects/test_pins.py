"""Pin groups in the simulation: which particles they hold, where (offsets, keys), how (soft
pins), the shorthand cloth.pinned, the app's pin gesture, and the refusals."""

import numpy as np
import pytest

from cloth_tui import scene_files as sf
from cloth_tui.pin_groups import SOFT_PIN_SCALE, PinGroup
from cloth_tui.scene import SceneError, SceneObject
from cloth_tui.sim.collision.held_contacts import check_start
from cloth_tui.sim.model import build_model
from cloth_tui.sim.effects.pins import group_particles, track_times
from cloth_tui.sim.run.runner import Simulation

from ..helpers import run, scene

N = 8


def pinned_scene(groups: str, *extra: str, pinned: str = "none"):
    return sf.apply_overrides(scene(cloth__resolution=N, cloth__pinned=pinned),
                              [f"pins={groups}", *extra])


def model_of(s):
    return build_model(s.cloth, s.behavior, s.pins)


def test_groups_choose_blocks_and_cells_by_row_and_column():
    g = PinGroup(rows=[-2, -1], cols=[1, 2])
    assert list(group_particles(g, 4, 5, "g")) == [11, 12, 16, 17]
    assert list(group_particles(PinGroup(at=[[0, -1], [0, -1], [1, 0]]), 4, 5, "g")) == [4, 5]
    assert list(group_particles(PinGroup(cols=[0, 0]), 3, 5, "g")) == [0, 5, 10]


def test_cloth_pinned_is_shorthand_for_the_same_groups():
    corners = run(Simulation(scene(cloth__resolution=N)), 20)
    groups = run(Simulation(pinned_scene("[{at=[[0,0],[0,-1],[-1,0],[-1,-1]]}]")), 20)
    assert list(groups.model.pinned) == list(corners.model.pinned)
    assert np.array_equal(groups.state.x, corners.state.x)


def test_a_hard_group_is_held_at_its_offset_from_the_start():
    sim = Simulation(pinned_scene("[{rows=[0,0], offset=[0.1,0.2,-0.05]}]"))
    rest = sim.model.rest_positions[:N]
    for frames in (0, 1, 30):
        run(sim, frames)
        assert np.allclose(sim.state.x[:N], rest + [0.1, 0.2, -0.05], atol=1e-12)


@pytest.mark.parametrize("solver", ["pbd", "hpbd", "xpbd", "springs"])
def test_a_moving_group_follows_its_keys(solver):
    keys = [[0.25, 0, 0, 0], [0.75, 0.3, 0.1, 0], [1.25, 0.3, 0.1, -0.2]]
    s = pinned_scene(f"[{{cols=[-1,-1], keys={keys}}}, {{cols=[0,0]}}]",
                     f"behavior.solver={solver}")
    sim = Simulation(s)
    right = np.arange(N) * N + N - 1
    rest = sim.model.rest_positions[right]
    expected = {0.0: (0, 0, 0), 0.25: (0, 0, 0), 0.5: (0.15, 0.05, 0), 0.75: (0.3, 0.1, 0),
                1.0: (0.3, 0.1, -0.1), 1.5: (0.3, 0.1, -0.2), 2.0: (0.3, 0.1, -0.2)}
    frame = 0
    for t, offset in expected.items():
        run(sim, round(t * 60) - frame)
        frame = round(t * 60)
        assert sim.state.t == pytest.approx(t)
        assert np.allclose(sim.state.x[right], rest + offset, atol=1e-9), t
    left = np.arange(N) * N
    assert np.allclose(sim.state.x[left], sim.model.rest_positions[left])  # the other group
    assert sim.stats().recoveries == 0


@pytest.mark.parametrize("substeps, iterations", [(4, 4), (16, 4), (4, 20)])
def test_a_soft_pin_settles_where_its_springs_carry_the_sheet(substeps, iterations):
    """A sheet hung by one soft edge alone: the springs, SOFT_PIN_SCALE·s/(1−s) N/m in all,
    carry its weight M·g, so the edge sags M·g/K, whatever the substeps and iterations."""
    s = pinned_scene("[{rows=[0,0], stiffness=0.5}]", "scene.floor=false",
                     "behavior.damping=0.1", f"behavior.substeps={substeps}",
                     f"behavior.iterations={iterations}", "behavior.adaptive=false")
    # 500 frames: hpbd's swing of this 8² sheet (one coarse level of 4 × 4) dies out later
    # than pbd's (|v| 1.8e-3 m/s at 300 frames, 6e-5 at 500)
    sim = run(Simulation(s), 500)
    k_total = SOFT_PIN_SCALE * 0.5 / 0.5
    sag = s.cloth.mass * s.forces.gravity_strength / k_total  # 1.96 cm
    dy = sim.state.x[:N, 1] - sim.model.rest_positions[:N, 1]
    assert float(np.abs(sim.state.v).max()) < 1e-3  # settled
    assert -dy.mean() == pytest.approx(sag, rel=0.01)
    assert len(sim.model.pinned) == 0  # soft pins keep their mass
    assert "soft_pins" in sim.step.names


def test_a_particle_two_groups_hold_differently_is_refused():
    with pytest.raises(SceneError, match=r"pins\[1\] and pins\[0\] both hold particle \[0, 7\] "
                                         "but differently"):
        check_start(pinned_scene("[{rows=[0,0]}, {cols=[-1,-1], offset=[0,0.1,0]}]"))
    check_start(pinned_scene("[{rows=[0,0]}, {cols=[-1,-1]}]"))  # the same hold: allowed


def test_a_group_that_moves_a_pattern_pin_says_to_leave_the_pattern_out():
    with pytest.raises(SceneError, match=r"pins\[0\] and cloth.pinned = \"corners\" both hold "
                                         r"particle \[0, 0\].*cloth.pinned = \"none\""):
        check_start(pinned_scene("[{at=[[0,0]], offset=[0.1,0,0]}]", pinned="corners"))


def test_the_command_line_refuses_conflicting_groups_with_exit_2(capsys):
    from cloth_tui.cli import main
    code = main(["simulate", "original", "--frames", "1", "--set",
                 "pins=[{at=[[0,0]], offset=[0.1,0,0]}]"])
    err = capsys.readouterr().err.strip()
    assert code == 2 and "\n" not in err and "both hold particle [0, 0]" in err


def test_an_object_on_a_moving_groups_track_is_refused():
    """The corner passes through a sphere half-way along its keys, not at the start."""
    sphere = SceneObject(type="sphere", center=[0.0, 0.25, -0.5], radius=0.1)
    s = pinned_scene("[{at=[[0,0]], keys=[[0,0,0,0],[2,1,0,0]]}]")
    s.objects = [sphere]
    with pytest.raises(SceneError, match=r"objects\[0\] \(a sphere\) encloses a held particle"):
        check_start(s)
    s.pins = [PinGroup(at=[[0, 0]], keys=[[0, 0, 0, 0], [2, 0, 0, 0.1]])]
    check_start(s)


def test_track_times_sample_every_key_and_the_moves_between():
    s = pinned_scene("[{at=[[0,0]], keys=[[0,0,0,0],[1,0.05,0,0],[3,0.05,0,0]]}]")
    times = track_times(model_of(s).pin_layout.hard)
    assert times[0] == 0 and times[-1] == 3 and 1.0 in times
    assert np.diff(times[times <= 1]).max() <= 0.2 + 1e-12  # 1 cm steps of a 5 cm move


def test_the_pin_gesture_holds_a_particle_where_it_is_released_until_a_restart():
    sim = run(Simulation(scene(cloth__resolution=N)), 5)
    middle = (N // 2) * N + N // 2
    target = [0.1, 0.4, 0.05]
    sim.pin(middle, target)
    run(sim, 30)
    assert np.allclose(sim.state.x[middle], target)
    assert middle in sim.model.pinned and sim.model.inv_mass[middle] == 0.0
    corner = 0
    sim.pin(corner, [-0.6, 0.3, -0.5])  # a pinned corner moves to where it is released
    run(sim, 5)
    assert np.allclose(sim.state.x[corner], [-0.6, 0.3, -0.5])
    sim.reset()
    assert middle not in sim.model.pinned
    assert np.allclose(sim.state.x[corner], sim.model.rest_positions[corner])


def test_the_pin_gesture_refuses_the_floor_and_objects_and_changes_nothing():
    s = scene(cloth__resolution=N, scene__object="sphere")
    sim = Simulation(s)
    before = sim.model
    with pytest.raises(SceneError, match="inside the floor"):
        sim.pin(9, [0, -0.6, 0])
    with pytest.raises(SceneError, match="encloses a held particle"):
        sim.pin(9, [0, -0.25, 0])  # the sphere's centre
    assert sim.model is before and len(sim.state.anchors) == len(before.pinned)


def test_the_pin_gesture_leaves_soft_and_moving_groups_alone():
    sim = Simulation(pinned_scene("[{at=[[0,0]], stiffness=0.5}, "
                                  "{at=[[1,1]], keys=[[0,0,0,0],[1,0,0.1,0]]}]"))
    for particle in (0, N + 1):
        with pytest.raises(SceneError, match="soft or moving pin group"):
            sim.pin(particle, [0, 0.3, 0])


def test_a_group_that_moves_a_wave_edge_is_refused_naming_the_wave():
    with pytest.raises(SceneError, match=r"pins\[0\] and behavior.wave both hold particle "
                                         r"\[0, 2\].*holds both its edges in place"):
        check_start(pinned_scene("[{at=[[0,2]], offset=[0,0.05,0]}]", "behavior.wave=true"))
    check_start(pinned_scene("[{at=[[0,2]]}, {at=[[3,3]], offset=[0,0.05,0]}]",
                             "behavior.wave=true"))
