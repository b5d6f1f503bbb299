"""A strip hung between two hooks closer together than its length settles into the
inextensible catenary: its sag is derived here from the catenary equation, not typed in."""

import math

import numpy as np
import pytest

from cloth_tui import scene_files as sf
from cloth_tui.scene import Scene
from cloth_tui.sim.run.runner import Simulation

LENGTH, WIDTH, SPAN = 1.0, 0.1, 0.8  # m: the strip, and its ends' distance once brought in


def catenary(span: float, length: float) -> tuple[float, float]:
    """(a, sag) of an inextensible chain of `length` hung between two points `span` apart at
    one height: y = a·cosh(x/a) with 2a·sinh(span/2a) = length, solved for a by bisection
    (the arc length falls monotonically as a grows), and sag = a·(cosh(span/2a) − 1)."""
    def arc(a: float) -> float:
        return 2 * a * math.sinh(span / (2 * a))
    lo, hi = span / 50, 100.0 * span  # arc(lo) ≫ length, arc(hi) ≈ span < length
    for _ in range(200):
        mid = 0.5 * (lo + hi)
        lo, hi = (mid, hi) if arc(mid) > length else (lo, mid)
    a = 0.5 * (lo + hi)
    return a, a * (math.cosh(span / (2 * a)) - 1)


def test_the_catenary_solution_checks_out():
    a, sag = catenary(SPAN, LENGTH)
    assert 2 * a * math.sinh(SPAN / (2 * a)) == pytest.approx(LENGTH, rel=1e-12)
    # cosh² − sinh² = 1 at the hooks: (a + sag)² − a² = (length/2)²
    assert (a + sag) ** 2 - a ** 2 == pytest.approx((LENGTH / 2) ** 2, rel=1e-12)
    # nearly taut, the parabola's sag √(3·span·(length − span)/8)
    _, shallow = catenary(1.0, 1.001)
    assert shallow == pytest.approx(math.sqrt(3 * 1.0 * 0.001 / 8), rel=1e-3)


def test_a_strip_between_two_hooks_sags_as_the_catenary():
    """1 m × 0.1 m at 41 × 5, bending off, both short ends held and brought 0.1 m in. The
    catenary is inextensible, so the strip must barely stretch: at this span a 1 mm longer
    strip sags about 0.5 mm more, hence many iterations and a 0.1 % stretch tolerance."""
    pull = (LENGTH - SPAN) / 2
    s = sf.apply_overrides(Scene(), [
        f"cloth.size=[{LENGTH}, {WIDTH}]", "cloth.resolution=[41, 5]", "cloth.pinned=none",
        "behavior.bending=false", "behavior.damping=0.1", "behavior.iterations=50",
        "behavior.error_tolerance=0.001",
        f"pins=[{{cols=[0,0], offset=[{pull},0,0]}}, {{cols=[-1,-1], offset=[{-pull},0,0]}}]"])
    sim = Simulation(s)
    for _ in range(600):
        sim.advance_frame()
    x = sim.state.x.reshape(5, 41, 3)
    assert float(np.abs(sim.state.v).max()) < 1e-3  # settled
    assert np.allclose(x[:, 0, 0], -SPAN / 2) and np.allclose(x[:, -1, 0], SPAN / 2)
    sag = float(np.mean(x[:, 0, 1] - x[:, 20, 1]))
    assert sag == pytest.approx(catenary(SPAN, LENGTH)[1], rel=0.01)
