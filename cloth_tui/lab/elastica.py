"""The heavy elastica: a strip clamped horizontally at s = 0, free at s = L, bending under
its own weight. With θ(s) the angle below horizontal, w the weight per unit length and
width and B the bending rigidity,

    B θ'' = −w (L − s) cos θ,   θ(0) = 0,   θ'(L) = 0,

which in s/L depends on one number, the load λ = wL³/B. Solved by shooting on the clamp's
curvature θ'(0), with RK4 and Newton's method on the sensitivity equations.
"""

from __future__ import annotations

import math
from dataclasses import dataclass

# Beyond about 150 the strip hangs nearly straight down and the shot grows too sensitive to
# the clamp's curvature for double precision to find it (cantilever then says so rather than
# answer); the lab's loads are at most 20, the reference table's 100.
MAX_LOAD = 100.0
STEPS = 800  # RK4 steps along the strip: δ/L within 2e-12 of 3200 steps' up to λ = 100


@dataclass(frozen=True)
class Cantilever:
    load: float           # λ = wL³/B
    tip_drop: float       # δ/L, vertical
    reach: float          # x/L of the tip, horizontal
    chord_angle: float    # rad, the line from the clamp to the tip below horizontal
    tip_slope: float      # rad, θ(L)
    clamp_curvature: float  # θ'(0)·L


def _shoot(load: float, k0: float) -> tuple[float, ...]:
    """Integrates from the clamp with θ'(0) = k0; returns θ'(1), ∂θ'(1)/∂k0, x(1), y(1),
    θ(1), the largest θ and the smallest θ' before the tip (lengths in units of L)."""
    h = 1.0 / STEPS

    def f(s, th, k, dth, dk):
        c, sn = math.cos(th), math.sin(th)
        return k, -load * (1 - s) * c, dk, load * (1 - s) * sn * dth, c, sn

    th, k, dth, dk, x, y = 0.0, k0, 0.0, 1.0, 0.0, 0.0
    highest, least_curvature = 0.0, k0
    for i in range(STEPS):
        s = i * h
        a = f(s, th, k, dth, dk)
        b = f(s + h / 2, th + h / 2 * a[0], k + h / 2 * a[1], dth + h / 2 * a[2],
              dk + h / 2 * a[3])
        c = f(s + h / 2, th + h / 2 * b[0], k + h / 2 * b[1], dth + h / 2 * b[2],
              dk + h / 2 * b[3])
        d = f(s + h, th + h * c[0], k + h * c[1], dth + h * c[2], dk + h * c[3])
        th += h / 6 * (a[0] + 2 * b[0] + 2 * c[0] + d[0])
        k += h / 6 * (a[1] + 2 * b[1] + 2 * c[1] + d[1])
        dth += h / 6 * (a[2] + 2 * b[2] + 2 * c[2] + d[2])
        dk += h / 6 * (a[3] + 2 * b[3] + 2 * c[3] + d[3])
        x += h / 6 * (a[4] + 2 * b[4] + 2 * c[4] + d[4])
        y += h / 6 * (a[5] + 2 * b[5] + 2 * c[5] + d[5])
        highest = max(highest, th)
        if i < STEPS - 1:
            least_curvature = min(least_curvature, k)
    return k, dk, x, y, th, highest, least_curvature


def cantilever(load: float) -> Cantilever:
    """The elastica at λ = wL³/B. The clamp's curvature lies in [0, λ/2] (the moment there
    is at most the whole weight's, wL²/2), and θ'(1) changes sign across that bracket. On
    the hanging strip θ' falls from the clamp to 0 at the tip and θ stays below 90°, so a
    shot that turns past the vertical is too curved and one whose θ' turns negative before
    the tip (the strip swinging back up) is not curved enough: that keeps the other roots
    of θ'(1) = 0, which curl or wave, out of the bracket. Newton's step is taken when it
    stays in the bracket and converges fast enough, else the bracket is halved."""
    if not 0 < load <= MAX_LOAD:
        raise ValueError(f"the load wL³/B must be in (0, {MAX_LOAD:g}], got {load}")
    lo, hi = 0.0, load / 2
    k0, last_step = load / 4, load / 2
    best = None
    for _ in range(200):
        end, slope, x, y, th, highest, least = _shoot(load, k0)
        if highest > math.pi / 2 + 1e-9:
            hi, k0, last_step = k0, 0.5 * (lo + k0), 0.5 * (k0 - lo)
            continue
        # a swing back is a θ' below zero of the order of the clamp's own; a shot just short
        # of the root dips below zero only in the last steps, by about its θ'(1)
        if least < -1e-3 * k0:
            lo, k0, last_step = k0, 0.5 * (k0 + hi), 0.5 * (hi - k0)
            continue
        best = (k0, x, y, th)
        if end < 0:
            lo = k0
        else:
            hi = k0
        if abs(end) < 1e-12 * max(1.0, load) or hi - lo < 1e-14 * hi:
            break
        newton = k0 - end / slope if slope > 0 else math.nan
        if lo < newton < hi and abs(2 * end) < abs(last_step * slope):
            k0, last_step = newton, abs(newton - k0)
        else:
            k0, last_step = 0.5 * (lo + hi), 0.5 * (hi - lo)
    else:
        raise ArithmeticError(f"the elastica at wL³/B = {load:g} did not converge")
    k0, x, y, th = best
    return Cantilever(load=load, tip_drop=y, reach=x, chord_angle=math.atan2(y, x),
                      tip_slope=th, clamp_curvature=k0)


def load_for_chord_angle(angle: float) -> float:
    """λ at which the line from the clamp to the tip falls `angle` (rad) below horizontal:
    the angle grows with the load, from 0 towards 90°, so regula falsi on log λ (Illinois'
    variant, which cannot stall at one end) inside a bracket finds it."""
    # the chord angles at loads 0.01 and MAX_LOAD are 0.07° and 80.4°
    if not math.radians(0.1) <= angle <= math.radians(80):
        raise ValueError(f"a chord angle from 0.1° to 80° is needed, got "
                         f"{math.degrees(angle):g}°")

    def chord(log_load: float) -> float:
        return cantilever(min(math.exp(log_load), MAX_LOAD)).chord_angle

    lo, hi = math.log(1e-2), math.log(MAX_LOAD)
    f_lo = chord(lo) - angle
    f_hi = chord(hi) - angle
    side = 0
    for _ in range(100):
        mid = (lo * f_hi - hi * f_lo) / (f_hi - f_lo)
        f = chord(mid) - angle
        if abs(f) < 1e-12 or hi - lo < 1e-12:
            return math.exp(mid)
        if f < 0:
            lo, f_lo = mid, f
            if side == -1:
                f_hi /= 2
            side = -1
        else:
            hi, f_hi = mid, f
            if side == 1:
                f_lo /= 2
            side = 1
    raise ArithmeticError(f"no load found for a chord angle of {math.degrees(angle):g}°")
