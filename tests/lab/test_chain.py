"""The hanging chain's swing: J₀'s zeros from its series, and the first mode of a chain of
lumped masses, solved as an eigenproblem, converging to ω₁ = (j₀,₁/2)√(g/L)."""

import math

import pytest

from cloth_tui.lab.chain import (bessel_j0, bessel_j0_zero, hanging_chain_omega,
                                 hanging_chain_period, lumped_chain_omega)


def test_the_zeros_of_j0():
    # Abramowitz & Stegun, table 9.5
    assert bessel_j0_zero(1) == pytest.approx(2.4048255577, abs=1e-10)
    assert bessel_j0_zero(2) == pytest.approx(5.5200781103, abs=1e-10)
    assert bessel_j0_zero(3) == pytest.approx(8.6537279129, abs=1e-10)


@pytest.mark.parametrize("x", [0.3, 1.7, 4.0, 8.5])
def test_the_series_solves_bessels_equation(x):
    """x·J₀'' + J₀' + x·J₀ = 0, with the derivatives by central differences."""
    h = 1e-3
    y0, yp, ym = bessel_j0(x), bessel_j0(x + h), bessel_j0(x - h)
    residual = x * (yp - 2 * y0 + ym) / h ** 2 + (yp - ym) / (2 * h) + x * y0
    assert abs(residual) < 1e-5
    assert bessel_j0(0.0) == 1.0 and bessel_j0(-x) == bessel_j0(x)


def test_the_period_of_a_one_metre_chain():
    assert hanging_chain_period(1.0, 9.81) == pytest.approx(1.668, abs=5e-4)
    assert hanging_chain_omega(4.0) == pytest.approx(hanging_chain_omega(1.0) / 2)


def test_a_chain_of_lumped_masses_converges_to_the_bessel_mode():
    exact = hanging_chain_omega(1.0, 9.81)
    errors = [abs(lumped_chain_omega(1.0, 9.81, n) / exact - 1) for n in (16, 32, 64, 128)]
    # measured: −0.12 % at 16 links, −0.002 % at 128, the error falling as h²
    assert errors[-1] < 1e-4
    orders = [math.log2(a / b) for a, b in zip(errors, errors[1:])]
    assert all(abs(p - 2) < 0.05 for p in orders), orders


@pytest.mark.parametrize("bad", [lambda: bessel_j0(12.0), lambda: bessel_j0_zero(4),
                                 lambda: hanging_chain_omega(0.0)])
def test_out_of_range_is_refused(bad):
    with pytest.raises(ValueError):
        bad()
