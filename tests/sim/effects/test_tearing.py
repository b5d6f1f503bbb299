"""Tearing: overstretched constraints break and leave the solve; cuts; restart heals."""

import numpy as np
import pytest

from cloth_tui.scene import Scene, SceneError
from cloth_tui.sim import pipeline
from cloth_tui.sim.effects import tearing
from cloth_tui.sim.run.measures import stretch
from cloth_tui.sim.model import build_model
from cloth_tui.sim.run.runner import Simulation
from cloth_tui.sim.state import ClothState


def pulled(tear: bool, solver: str = "pbd", g: float = 300.0, **behavior) -> Scene:
    """A sheet pinned along one edge, pulled down by a field 30× gravity."""
    s = Scene()
    s.cloth.pinned = "one_edge"
    s.cloth.height = 1.0
    s.scene.floor = False
    s.forces.gravity_strength = g
    b = s.behavior
    b.tear, b.solver, b.adaptive, b.tethers = tear, solver, False, False
    for k, v in behavior.items():
        setattr(b, k, v)
    return s


def run(scene: Scene, frames: int = 40) -> Simulation:
    sim = Simulation(scene)
    sim.peak_stretch = 0.0
    for _ in range(frames):
        sim.advance_frame()
        sim.peak_stretch = max(sim.peak_stretch, sim.stats().max_stretch)
    return sim


@pytest.mark.parametrize("solver, g, extra", [
    ("pbd", 300.0, {}),
    ("xpbd", 300.0, {"compliance": 1e-3}),
    ("springs", 3000.0, {}),  # implicit Euler
])
def test_a_sheet_pulled_beyond_tear_stretch_tears_and_stays_finite(solver, g, extra):
    sim = run(pulled(True, solver, g, **extra))
    st = sim.stats()
    assert st.torn > 0 and st.finite and np.isfinite(st.energy)
    assert st.torn == int((sim.state.alive == 0).sum())
    # what is left intact is held at no more than the tear stretch (measures skip the torn)
    assert st.max_stretch <= sim.scene.behavior.tear_stretch
    assert "tear_constraints" in st.effects


@pytest.mark.parametrize("solver, g, extra", [
    ("pbd", 300.0, {}),
    ("xpbd", 300.0, {"compliance": 1e-3}),
    ("springs", 3000.0, {}),
])
def test_the_same_pull_without_tear_does_not_tear(solver, g, extra):
    sim = run(pulled(False, solver, g, **extra))
    st = sim.stats()
    assert st.torn == 0 and st.finite
    assert bool(sim.state.alive.all())
    if solver != "springs":  # (springs exceed it between frames, where stats do not look)
        assert sim.peak_stretch > sim.scene.behavior.tear_stretch  # it would have torn
    assert "tear_constraints" not in st.effects


def test_torn_constraints_leave_every_solver():
    """A torn constraint exerts nothing: two particles joined only by torn constraints fly
    apart freely, in each solver."""
    for solver in ("pbd", "hpbd", "xpbd", "springs"):
        s = Scene()
        s.cloth.resolution = 2
        s.cloth.pinned = "none"
        s.forces.gravity = False
        s.scene.floor = False
        s.behavior.solver = solver
        s.behavior.adaptive = False
        s.behavior.damping = 0.0
        s.behavior.spring_damping = 0.0
        model = build_model(s.cloth, s.behavior)
        step = pipeline.build(s, model)
        state = ClothState.from_model(model)
        state.alive[:] = 0
        state.torn = model.num_constraints
        state.v[0] = (-1.0, 0.0, 0.0)
        state.x[0, 0] -= 0.5  # far beyond rest length: an intact constraint would pull back
        x0 = state.x.copy()
        step.frame(state)
        h = step.h * step.substeps
        np.testing.assert_allclose(state.x[0], x0[0] + h * np.array([-1.0, 0, 0]), atol=1e-9,
                                   err_msg=solver)
        np.testing.assert_allclose(state.x[1:], x0[1:], atol=1e-12, err_msg=solver)


def test_break_kernel_counts_only_new_breaks():
    s = Scene()
    model = build_model(s.cloth, s.behavior)
    state = ClothState.from_model(model)
    state.x[0, 0] -= 0.5 * model.spacing  # stretches the constraints at particle 0
    k = tearing.break_overstretched_constraints(state.x, model.edges, model.rest_length,
                                                state.alive, 0.3)
    assert k == int((state.alive == 0).sum()) > 0
    assert tearing.break_overstretched_constraints(state.x, model.edges, model.rest_length,
                                                   state.alive, 0.3) == 0


def test_a_cut_breaks_the_constraints_it_crosses_and_restart_heals():
    s = Scene()
    s.cloth.resolution = 10
    sim = Simulation(s)
    n = sim.model.nx
    cut = sim.cut(4 * n + 0, 4 * n + (n - 1))  # along row 4, across the whole sheet
    assert cut > 0 and sim.state.torn == cut
    e = sim.model.edges
    gone = e[sim.state.alive == 0]
    rows = np.sort(gone // n, axis=1)
    # every vertical structural edge between rows 4 and 5 is cut, and only crossing ones
    assert {(a, b) for a, b in rows} <= {(4, 5), (3, 5), (4, 6)}
    vertical = (e[:, 1] - e[:, 0] == n) & (e[:, 0] // n == 4)
    assert (sim.state.alive[vertical] == 0).all()
    assert sim.cut(3, 3) == 0  # the same particle twice cuts nothing
    # intact elsewhere: the rendered triangles lose exactly one row of cells
    tri = tearing.intact_triangles(sim.model, sim.state.alive)
    assert len(tri) == len(sim.model.triangles) - 2 * (n - 1)
    sim.advance_frame()
    assert sim.stats().torn == cut and sim.snapshot().alive is not None
    sim.reset()
    assert sim.stats().torn == 0 and sim.state.alive.all()
    assert sim.snapshot().alive is None


def test_tear_turns_tethers_off_and_a_cut_stops_them():
    s = Scene()
    s.cloth.pinned = "one_edge"
    assert build_model(s.cloth, s.behavior).tether_pin is not None
    s.behavior.tear = True
    assert build_model(s.cloth, s.behavior).tether_pin is None
    # tear = false: the tethers run until something is cut, then no more
    s.behavior.tear = False
    sim = Simulation(s)
    assert "enforce_tethers" in sim.step.names
    sim.cut(5 * 26 + 0, 5 * 26 + 25)
    for _ in range(30):
        sim.advance_frame()
    # the part below the cut falls away: farther from the pins than tethers would allow
    i = np.arange(26 * 26) // 26
    assert sim.state.x[i > 6, 1].max() < sim.state.x[i < 4, 1].min() - 0.1


def test_tear_stretch_is_validated():
    with pytest.raises(SceneError, match="tear_stretch"):
        Scene().with_value("behavior.tear_stretch", 0.0)
    assert Scene().with_value("behavior.tear_stretch", 0.1).behavior.tear_stretch == 0.1


def test_stretch_skips_torn_constraints():
    s = Scene()
    model = build_model(s.cloth, s.behavior)
    x = np.array(model.rest_positions)
    x[0, 0] -= 1.0
    alive = np.ones(model.num_constraints, np.uint8)
    assert stretch(model, x, alive)[0] > 1.0
    e = model.edges
    alive[(e[:, 0] == 0) | (e[:, 1] == 0)] = 0
    assert stretch(model, x, alive)[0] == pytest.approx(0.0, abs=1e-12)


def test_compression_breaks_nothing():
    """Cloth tears in tension only: a fold squeezes constraints without harm."""
    s = Scene()
    model = build_model(s.cloth, s.behavior)
    state = ClothState.from_model(model)
    state.x[0, 0] += 0.6 * model.spacing  # 60 % shorter than rest towards particle 1
    assert tearing.break_overstretched_constraints(state.x, model.edges, model.rest_length,
                                                   state.alive, 0.3) == 0
    assert state.alive.all()


def test_a_torn_sheet_still_collides_with_objects_and_itself():
    """Torn pieces fall onto a sphere and the floor with self-collision on: no penetration,
    finite, and the broken sheet keeps its mass."""
    s = pulled(True, "pbd", 300.0)
    s.scene.floor = True
    s.cloth.height = 0.6
    s.scene.object = "sphere"
    s.behavior.self_collision = "hash"
    sim = run(s, frames=60)
    st = sim.stats()
    assert st.torn > 0 and st.finite
    assert "collide_sphere" in st.effects and "self_collision_hash" in st.effects
    assert st.penetration <= s.scene.thickness + 1e-3
    assert st.min_y >= s.scene.floor_height - 1e-3
    assert sim.model.mass.sum() == pytest.approx(s.cloth.mass)


def test_a_particle_whose_every_constraint_is_torn_is_left_where_it_was():
    # Through the solver's own projection (grid_sweeps' colour sweeps, serial or parallel as
    # chosen); tests/sim/test_grid_sweeps.py checks the sweeps skip exactly the torn
    # constraints the plain loop skips, for both kernels.
    from cloth_tui.sim.solvers.xpbd import constraints as xpbd
    from cloth_tui.sim.state import ClothState
    s = Scene()
    s.cloth.resolution = 40
    m = build_model(s.cloth, s.behavior)
    rng = np.random.default_rng(2)
    state = ClothState.from_model(m)
    state.x += rng.normal(scale=0.01, size=state.x.shape)
    x0 = state.x.copy()
    e, mid = m.edges, 20 * 40 + 20  # a free particle
    state.alive[(e[:, 0] == mid) | (e[:, 1] == mid)] = 0
    xpbd.ProjectConstraints(m, 3, 0.0, 1e-3, "pbd").apply(state, 1e-3)
    np.testing.assert_array_equal(state.x[mid], x0[mid])
    assert np.abs(state.x[mid + 1] - x0[mid + 1]).max() > 0.0


def test_the_torn_count_grows_in_one_place_only():
    """Every break, by load, by a cut or by taking constraints out (the lab's disc), goes
    through tearing.py; no other module writes state.torn."""
    import re
    from pathlib import Path

    import cloth_tui
    root = Path(cloth_tui.__file__).parent
    writes = re.compile(r"\bstate\.torn\s*(\+|-)?=(?!=)")
    found = [str(p.relative_to(root)) for p in sorted(root.rglob("*.py"))
             if writes.search(p.read_text(encoding="utf-8"))]
    assert found == ["sim/effects/tearing.py"]
    assert writes.search("sim.state.torn += 3") and not writes.search("if state.torn == 0:")


def test_removing_constraints_counts_only_those_still_intact():
    from cloth_tui.sim.effects.tearing import remove_constraints
    sim = Simulation(Scene().with_value("cloth.resolution", 4))
    mask = np.zeros(sim.model.num_constraints, dtype=bool)
    mask[:5] = True
    assert remove_constraints(sim.state, mask) == 5 and sim.state.torn == 5
    mask[:8] = True
    assert remove_constraints(sim.state, mask) == 3 and sim.state.torn == 8
    assert (sim.state.alive[:8] == 0).all() and sim.state.alive[8:].all()
