"""The hanging chain's swing: a uniform chain (or a strip without bending stiffness) of
length L hanging from its top end swings in modes ω_k = (j₀,ₖ/2)·√(g/L), with j₀,ₖ the
k-th zero of the Bessel function J₀ (Bernoulli, Euler). The zero is computed here from J₀'s
power series; a chain of equal links with lumped masses (what a grid of particles is) is
solved as an eigenproblem."""

from __future__ import annotations

import math


def bessel_j0(x: float) -> float:
    """J₀(x) = Σ (−1)ᵐ (x/2)²ᵐ / (m!)², summed until the terms no longer matter; accurate
    to ~1e-15 for |x| ≤ 10 (beyond, the series' cancellation loses digits)."""
    if abs(x) > 10:
        raise ValueError(f"the power series of J0 is used only for |x| <= 10, got {x}")
    q = -(x / 2) ** 2
    term, total, m = 1.0, 1.0, 0
    while abs(term) > 1e-17 * max(1.0, abs(total)):
        m += 1
        term *= q / (m * m)
        total += term
    return total


def bessel_j0_zero(k: int = 1) -> float:
    """The k-th positive zero of J₀ (k ≤ 3 within the series' range), bracketed by a scan
    and refined by bisection."""
    if not 1 <= k <= 3:
        raise ValueError(f"zeros 1 to 3 of J0 are available, got {k}")
    step, x, found = 0.05, 0.0, 0
    while True:
        if bessel_j0(x) * bessel_j0(x + step) < 0:
            found += 1
            if found == k:
                break
        x += step
    lo, hi = x, x + step
    for _ in range(80):
        mid = 0.5 * (lo + hi)
        if bessel_j0(lo) * bessel_j0(mid) <= 0:
            hi = mid
        else:
            lo = mid
    return 0.5 * (lo + hi)


def hanging_chain_omega(length: float, gravity: float = 9.81, mode: int = 1) -> float:
    """rad/s: the angular frequency of the chain's mode `mode`."""
    if not (length > 0 and gravity > 0):
        raise ValueError(f"length and gravity must be positive, got {length}, {gravity}")
    return bessel_j0_zero(mode) / 2 * math.sqrt(gravity / length)


def hanging_chain_period(length: float, gravity: float = 9.81, mode: int = 1) -> float:
    """s: 2π/ω of the mode."""
    return 2 * math.pi / hanging_chain_omega(length, gravity, mode)


def lumped_chain_omega(length: float, gravity: float, links: int) -> float:
    """rad/s: the lowest angular frequency of `links` equal links with the mass lumped at
    the joints (half at the free end), hung from a pin: M ü = −K u, each link's tension the
    weight below it. The exact answer for the grid, which converges to the chain's as h²."""
    import numpy as np  # here only: the rest of the lab's expectations are plain math

    if links < 1:
        raise ValueError(f"a chain needs at least one link, got {links}")
    h = length / links
    m = np.full(links, 1.0)
    m[-1] = 0.5
    tension = gravity * np.array([m[k:].sum() for k in range(links)])  # link k above joint k
    k = np.zeros((links, links))
    for j in range(links):
        k[j, j] += tension[j] / h
        if j + 1 < links:
            k[j, j] += tension[j + 1] / h
            k[j, j + 1] -= tension[j + 1] / h
            k[j + 1, j] -= tension[j + 1] / h
    s = 1 / np.sqrt(m)
    return math.sqrt(float(np.linalg.eigvalsh(s[:, None] * k * s[None, :]).min()))
