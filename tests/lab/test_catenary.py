"""The catenary's sag: the Newton solve satisfies its own equation from taut to slack, a
chain of equal links solved independently converges to it as h², and the small-sag limit
is the parabola's."""

import math

import pytest

from cloth_tui.lab.catenary import catenary, chain_sag


def test_the_reference_catenary():
    # computed independently for the project's reference notes: span 0.8 m, length 1 m
    c = catenary(0.8, 1.0)
    assert c.a == pytest.approx(0.33820, abs=5e-6)
    assert c.sag == pytest.approx(0.26544, abs=5e-6)
    assert math.degrees(c.pin_slope) == pytest.approx(55.93, abs=0.005)


@pytest.mark.parametrize("ratio", [1.000001, 1.001, 1.25, 2.0, 10.0, 1000.0])
def test_the_solution_has_the_chains_length(ratio):
    span = 0.8
    c = catenary(span, span * ratio)
    assert 2 * c.a * math.sinh(span / (2 * c.a)) == pytest.approx(span * ratio, rel=1e-12)
    assert c.sag == pytest.approx(c.a * (math.cosh(span / (2 * c.a)) - 1), rel=1e-12)


def test_a_nearly_taut_chain_sags_as_the_parabola():
    span, length = 1.0, 1.001
    assert catenary(span, length).sag == pytest.approx(math.sqrt(3 * span * (length - span) / 8),
                                                       rel=1e-3)


def test_a_chain_of_equal_links_converges_to_it_as_h_squared():
    exact = catenary(0.8, 1.0).sag
    errors = {n: chain_sag(0.8, 1.0, n) / exact - 1 for n in (8, 16, 32, 64)}
    # the reference notes' lumped chain: +0.85 % at 8 links, +0.21 % at 16, +0.05 % at 32
    assert errors[8] == pytest.approx(0.0085, abs=5e-4)
    assert errors[16] == pytest.approx(0.0021, abs=5e-4)
    assert errors[32] == pytest.approx(0.0005, abs=5e-4)
    orders = [math.log2(errors[n] / errors[2 * n]) for n in (8, 16, 32)]
    assert all(abs(p - 2) < 0.05 for p in orders), orders


@pytest.mark.parametrize("span, length", [(1.0, 1.0), (1.0, 0.5), (0.0, 1.0), (-1, 1)])
def test_a_chain_that_cannot_hang_is_refused(span, length):
    with pytest.raises(ValueError, match="0 < span < length"):
        catenary(span, length)
