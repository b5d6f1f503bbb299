"""Force-based springs solver: each integrator on a single spring, and on the cloth."""

import math
from types import SimpleNamespace

import numpy as np
import pytest

from cloth_tui.bench import accuracy as A
from cloth_tui.scene import Scene
from cloth_tui.sim import pipeline
from cloth_tui.sim.run.runner import Simulation
from cloth_tui.sim.params import StepParams
from cloth_tui.sim.solvers.springs.integrators import MOVE_LIMIT, ORDERS, IntegrateSprings
from cloth_tui.sim.state import ClothState

K, M, L0, AMP = 40.0, 0.1, 1.0, 0.05   # ω = 20 rad/s, period ≈ 0.314 s



def spring_params(b) -> StepParams:
    return StepParams(stiffness=b.stiffness, spring_damping=b.spring_damping, damping=b.damping)

def oscillator(integrator, damping=0.0):
    """Particle 0 pinned at the origin, particle 1 (mass M) on a spring of stiffness K."""
    model = SimpleNamespace(
        num_particles=2, num_constraints=1, edges=np.array([[0, 1]], np.int64),
        rest_length=np.array([L0]), mass=np.array([M, M]), inv_mass=np.array([0.0, 1.0 / M]),
        pinned=np.array([0], np.int64))
    b = SimpleNamespace(integrator=integrator, stiffness=K, spring_damping=damping, damping=0.0)
    x = np.array([[0.0, 0, 0], [L0 + AMP, 0, 0]])
    state = SimpleNamespace(x=x, x_prev=x.copy(), v=np.zeros((2, 3)), accel=np.zeros((2, 3)),
                            alive=np.ones(1, np.uint8), t=0.0)
    return IntegrateSprings(model, b, [], spring_params(b)), state


def run_oscillator(integrator, h, t_end):
    eff, st = oscillator(integrator)
    xs, es = [], []
    for _ in range(int(round(t_end / h))):
        eff.apply(st, h)
        st.t += h
        u = st.x[1, 0] - L0
        xs.append(u)
        es.append(0.5 * M * st.v[1, 0] ** 2 + 0.5 * K * u * u)
    return np.array(xs), np.array(es), st


def test_rk4_period_matches_two_pi_sqrt_m_over_k():
    h = 1e-3
    xs, _, _ = run_oscillator("rk4", h, 3.0)
    t = (np.arange(len(xs)) + 1) * h
    # upward zero crossings, linearly interpolated
    i = np.nonzero((xs[:-1] < 0) & (xs[1:] >= 0))[0]
    tc = t[i] - xs[i] * h / (xs[i + 1] - xs[i])
    period = np.mean(np.diff(tc))
    assert period == pytest.approx(2 * math.pi * math.sqrt(M / K), rel=1e-4)


@pytest.mark.parametrize("integrator", list(ORDERS))
def test_energy_drift_sign(integrator):
    """Explicit Euler and midpoint gain energy, implicit Euler and RK4 lose it; symplectic
    Euler and Verlet keep it bounded (oscillating, no drift)."""
    e0 = 0.5 * K * AMP * AMP
    _, es, _ = run_oscillator(integrator, 0.01, 6.0)  # hω = 0.2, ~19 periods
    drift = (es[-200:].mean() - e0) / e0
    if integrator == "explicit_euler":
        assert drift > 1.0
    elif integrator == "midpoint":
        assert drift > 1e-4
    elif integrator == "implicit_euler":
        assert drift < -0.5
    elif integrator == "rk4":
        assert -1e-3 < drift < 0
    else:  # symplectic: bounded, no secular drift
        assert abs(drift) < 0.02
        assert np.max(np.abs(es / e0 - 1)) < 0.25


def test_implicit_euler_stable_where_explicit_blows_up():
    cfg = A.StudyConfig(stiffness=2000.0, t_end=0.5)
    dt = 1.0 / 240
    ex = A.simulate(A.study_scene(cfg, "springs", "explicit_euler", dt),
                    A.study_model(A.study_scene(cfg)), cfg.t_end)
    im = A.simulate(A.study_scene(cfg, "springs", "implicit_euler", dt),
                    A.study_model(A.study_scene(cfg)), cfg.t_end)
    assert not ex.stable
    assert im.stable and im.stretch < 0.2


@pytest.mark.parametrize("integrator", ["verlet", "rk4", "symplectic_euler"])
def test_free_fall(integrator):
    s = Scene()
    for k, v in (("cloth.pinned", "none"), ("cloth.resolution", 6), ("scene.floor", False),
                 ("behavior.damping", 0.0), ("behavior.solver", "springs"),
                 ("behavior.stiffness", 10.0), ("behavior.spring_damping", 0.0),
                 ("behavior.integrator", integrator)):
        s = s.with_value(k, v)
    sim = Simulation(s)
    y0 = sim.state.x[:, 1].copy()
    for _ in range(30):
        sim.advance_frame()
    t = sim.state.t
    tol = 1e-9 if integrator != "symplectic_euler" else 9.81 * t * sim.step.h
    np.testing.assert_allclose(y0 - sim.state.x[:, 1], 0.5 * 9.81 * t * t, atol=tol)
    np.testing.assert_allclose(sim.state.v[:, 1], -9.81 * t, atol=1e-9)


@pytest.mark.parametrize("integrator", list(ORDERS))
def test_pins_contacts_and_velocities_with_every_integrator(integrator):
    """Corner-pinned sheet falling onto a near floor: pins stay at their anchors, nobody
    goes through the floor, velocities stay finite and consistent."""
    s = Scene()
    for k, v in (("cloth.resolution", 8), ("scene.floor_height", 0.1),
                 ("behavior.solver", "springs"), ("behavior.integrator", integrator),
                 ("behavior.stiffness", 100.0), ("behavior.spring_damping", 0.01),
                 ("behavior.substeps", 100)):
        s = s.with_value(k, v)
    sim = Simulation(s)
    names = sim.step.names
    assert names[0] == f"integrate_{integrator}" and names[-1] == "correct_velocities"
    for _ in range(40):
        sim.advance_frame()
    m = sim.model
    assert sim.recoveries == 0
    np.testing.assert_array_equal(sim.state.x[m.pinned], m.rest_positions[m.pinned])
    np.testing.assert_array_equal(sim.state.v[m.pinned], 0.0)
    assert sim.state.x[:, 1].min() >= 0.1 + s.scene.thickness - 1e-12
    assert sim.state.is_finite() and np.abs(sim.state.v).max() < 10


def test_force_effects_are_evaluated_through_the_protocol():
    """A force effect is evaluated through `accumulate` at every stage; a kinematic one (the
    wave) through `apply`, once per substep, never as a force."""
    class Pull:
        name, kinematic = "pull", False

        def accumulate(self, x, v, t, out_accel):
            out_accel[:, 1] -= 1.0

        def apply(self, state, h):
            raise AssertionError("a force-based integrator evaluates forces by accumulate")

    class Drive:
        name, kinematic = "drive", True
        calls = 0

        def accumulate(self, x, v, t, out_accel):
            raise AssertionError("a kinematic effect is not a force")

        def apply(self, state, h):
            Drive.calls += 1

    model = SimpleNamespace(
        num_particles=2, num_constraints=1, edges=np.array([[0, 1]], np.int64),
        rest_length=np.array([L0]), mass=np.array([M, M]), inv_mass=np.array([0.0, 1.0 / M]),
        pinned=np.array([0], np.int64))
    b = SimpleNamespace(integrator="rk4", stiffness=K, spring_damping=0.0, damping=0.0)
    eff = IntegrateSprings(model, b, [Pull(), Drive()], spring_params(b))
    out = eff.accel(np.array([[0.0, 0, 0], [L0, 0, 0]]), np.zeros((2, 3)), 0.0, np.zeros((2, 3)))
    np.testing.assert_allclose(out, [[0, 0, 0], [0, -1.0, 0]])
    _, state = oscillator("rk4")
    for _ in range(3):
        eff.apply(state, 0.01)
    assert Drive.calls == 3  # rk4 has 4 stages per substep: once per substep, not per stage


def test_implicit_euler_cg_converges_within_cap():
    s = A.study_scene(A.StudyConfig(stiffness=2000.0), "springs", "implicit_euler", 1 / 240)
    model = A.study_model(s)
    step = pipeline.build(s, model)
    st = ClothState.from_model(model)
    for _ in range(10):
        step.substep(st)
    from cloth_tui.sim.solvers.springs.integrators import CG_MAX_ITERATIONS
    assert 0 < step.effects[0].cg_iterations < CG_MAX_ITERATIONS


@pytest.mark.parametrize("integrator", list(ORDERS))
def test_a_move_far_past_the_speed_limit_is_cut_back_along_its_path(integrator):
    eff, st = oscillator(integrator)
    st.v[1] = [3e5, -4e5, 0.0]  # 500 km/s, ten thousand times max_speed
    h = 0.01
    eff.apply(st, h)
    move = st.x[1] - st.x_prev[1]
    reach = MOVE_LIMIT * eff.params.max_speed * h
    assert np.linalg.norm(move) == pytest.approx(reach, rel=1e-9)
    assert move[0] > 0 and move[1] < 0  # along the path it was given, not elsewhere


def test_a_move_within_the_limit_is_left_as_it_is():
    eff, st = oscillator("rk4")
    st.v[1] = [0.0, -2.0 * eff.params.max_speed, 0.0]  # past the speed limit, not far past
    eff.apply(st, 0.01)
    assert -st.x[1, 1] > 0.01 * eff.params.max_speed  # the integrator's own move


def test_a_torn_stiff_sheet_stays_where_the_floor_can_hold_it():
    """Every spring of a stiff implicit-Euler sheet torn at once under a fast wave (a fuzzed
    scene): the linearised step asked for moves of 10²⁰ m, which the floor's projection
    rounded to its height from below (5 cm of penetration)."""
    s = Scene()
    for k, v in (("forces.wind", True), ("forces.wind_direction", [-0.68, -0.19, -0.35]),
                 ("forces.custom_strength", 0.163), ("forces.rain_strength", 1.77),
                 ("scene.floor_height", 0.058), ("scene.object", "sphere"),
                 ("scene.friction", 0.9), ("scene.moving", True),
                 ("behavior.solver", "springs"), ("behavior.integrator", "implicit_euler"),
                 ("behavior.compliance", 1e-8), ("behavior.damping", 4.3e-5),
                 ("behavior.tear", True), ("behavior.tear_stretch", 1e-5),
                 ("behavior.wave_frequency", 37.56), ("behavior.wave_amplitude", 0.1),
                 ("behavior.frame_rate", 2.23), ("behavior.max_speed", 24.0),
                 ("behavior.max_substeps", 7)):
        s = s.with_value(k, v)
    sim = Simulation(s)
    start = sim.state.x.copy()
    for _ in range(4):
        sim.advance_frame()
    stats = sim.stats()
    assert stats.torn > 0.9 * len(sim.model.edges)
    reach = MOVE_LIMIT * 24.0 * sim.state.t
    assert np.linalg.norm(sim.state.x - start, axis=1).max() <= reach * (1 + 1e-9)
    assert stats.penetration == 0.0
