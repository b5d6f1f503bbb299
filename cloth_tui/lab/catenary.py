"""The inextensible catenary: a chain (or a strip without bending stiffness) of length L
hung between two pins at the same height, a span s apart. Its shape is y = a·cosh(x/a) − a
with a fixed by the length: L = 2a·sinh(s/(2a))."""

from __future__ import annotations

import math
from dataclasses import dataclass


@dataclass(frozen=True)
class Catenary:
    span: float       # m, between the pins
    length: float     # m, of the chain
    a: float          # m, the catenary's parameter (horizontal tension / weight per length)
    sag: float        # m, from the pins down to the lowest point
    pin_slope: float  # rad, below horizontal at the pins


def catenary(span: float, length: float) -> Catenary:
    """Solves sinh(y)/y = L/s for y = s/(2a) by Newton's method, kept inside a bracket that
    always holds the root (so it cannot diverge however slack or taut the chain)."""
    if not (span > 0 and length > span):
        raise ValueError(f"a catenary needs 0 < span < length, got span={span}, "
                         f"length={length}")
    ratio = length / span
    lo, hi = 0.0, 1.0
    while math.sinh(hi) / hi < ratio:
        hi *= 2
    y = min(math.sqrt(6 * (ratio - 1)), hi) or hi / 2  # sinh(y)/y ≈ 1 + y²/6 when taut
    for _ in range(200):
        f = math.sinh(y) / y - ratio
        if f > 0:
            hi = y
        else:
            lo = y
        df = (y * math.cosh(y) - math.sinh(y)) / (y * y)
        step = y - f / df if df > 0 else None
        y = step if step is not None and lo < step < hi else 0.5 * (lo + hi)
        if hi - lo < 1e-15 * hi or abs(f) < 1e-15 * ratio:
            break
    a = span / (2 * y)
    return Catenary(span=span, length=length, a=a, sag=a * (math.cosh(y) - 1),
                    pin_slope=math.atan(math.sinh(y)))


def chain_sag(span: float, length: float, links: int) -> float:
    """m: the sag of a chain of `links` equal rigid links with the mass lumped at the joints
    (what a grid of particles is), solved exactly: the horizontal tension H is the same in
    every link, and the vertical force drops by one joint's weight m·g at each joint, so
    link k's slope is tan φ_k = c·((links − 1)/2 − k) with c = m·g/H fixed by the span."""
    if links < 2:
        raise ValueError(f"a hanging chain needs at least 2 links, got {links}")
    h = length / links
    slopes = [(links - 1) / 2 - k for k in range(links)]

    def reach(c: float) -> float:
        return sum(h / math.sqrt(1 + (c * t) ** 2) for t in slopes)

    lo, hi = 0.0, 1.0
    while reach(hi) > span:
        hi *= 2
    for _ in range(200):
        mid = 0.5 * (lo + hi)
        if reach(mid) > span:
            lo = mid
        else:
            hi = mid
    c = 0.5 * (lo + hi)
    return sum(h * c * t / math.sqrt(1 + (c * t) ** 2) for t in slopes if t > 0)
