"""A measured fabric's stretch that stiffens with strain and its bending by direction, as
ARCSim's data-driven model (Wang, O'Brien & Ramamoorthi 2011) makes them of its samples.

Stretch: ARCSim stores a stiffness sample [C11, C12, C22, C33] at zero strain and five more at
a principal strain of 1/6, one per direction of that strain (0°, 22.5°, 45°, 67.5°, 90° to the
warp). Its dde.cpp doubles them and interpolates linearly in the principal stretch λ between
the zero-strain sample and the direction's own, reaching it at λ − 1 = 1/6 and staying there;
the stress is that stiffness times the Green strain G = ε + ε²/2 (physics.cpp). A strip pulled
along the warp by an engineering strain ε, its width held, so has the tension per unit of rest
width (the first Piola stress)

    T(ε) = (1 + ε) · k(ε) · (ε + ε²/2),  k(ε) = 2·(C_low + (C_high − C_low)·min(ε/reach, 1))

with C = C11 (warp, the 0° sample) or C22 (weft, the 90° sample). Under compression ARCSim
keeps the zero-strain sample; here the tension there is linear, k(0)·ε, today's model.

Bending: ARCSim stores three rows of hinge stiffness, for hinges (fold lines) at 0°, 45° and
90° to the warp; B = k/4 each (presets.py). A fold along the warp curves the fabric along
the weft, so B₀ is the rigidity of curvature along z and B₉₀ along x. docs/physics.md
("Measured fabrics: stiffening and direction") derives the grid's mapping.

Pure Python, like the rest of the package.
"""

from __future__ import annotations

import math
from dataclasses import dataclass

ARCSIM_STRAIN_REACH = 1.0 / 6.0  # dde.cpp: strain_value = (λ − 1)·6, clamped to [0, 1]


@dataclass(frozen=True)
class StretchCurve:
    """Tension per unit width against strain along one direction (module docstring)."""
    low: float                        # N/m, the stiffness k at zero strain (= stretch)
    high: float                       # N/m, k at strain `reach` and beyond
    reach: float = ARCSIM_STRAIN_REACH

    def stiffness(self, strain: float) -> float:
        """k(ε), N/m: the stiffness on the Green strain at engineering strain ε."""
        s = min(max(strain / self.reach, 0.0), 1.0)
        return self.low + (self.high - self.low) * s

    def secant(self, strain: float) -> float:
        """T(ε)/ε, N/m: the linear stiffness that gives the curve's tension at ε."""
        if strain <= 0.0:
            return self.low
        return self.stiffness(strain) * (1.0 + strain) * (1.0 + 0.5 * strain)

    def tension(self, strain: float) -> float:
        """T(ε), N/m of rest width."""
        return self.secant(strain) * strain

    def tangent(self, strain: float) -> float:
        """dT/dε, N/m: how fast the tension grows at strain ε."""
        if strain <= 0.0:
            return self.low
        slope = (self.high - self.low) / self.reach if strain < self.reach else 0.0
        green = strain * (1.0 + strain) * (1.0 + 0.5 * strain)
        return (slope * green
                + self.stiffness(strain) * (1.0 + 3.0 * strain + 1.5 * strain * strain))

    def strain_at(self, tension: float) -> float:
        """The strain ε ≥ 0 at which T(ε) = `tension` (≥ 0), by bisection: T grows with ε."""
        lo, hi = 0.0, 1.0
        while self.tension(hi) < tension:
            hi *= 2.0
        for _ in range(60):
            mid = 0.5 * (lo + hi)
            lo, hi = (mid, hi) if self.tension(mid) < tension else (lo, mid)
        return 0.5 * (lo + hi)


@dataclass(frozen=True)
class BendingByDirection:
    """Bending rigidities (N·m) of folds at 0°, 45° and 90° to the warp."""
    fold_0: float    # a fold along the warp: curvature along the weft (z)
    fold_45: float   # a bias fold
    fold_90: float   # a fold along the weft: curvature along the warp (x)

    @classmethod
    def of_strips(cls, warp: float, weft: float) -> "BendingByDirection":
        """The folds of a fabric whose strips cut along the warp and along the weft (ASTM
        D1388's two) have rigidities `warp` and `weft`: the warp strip curves along x, a fold
        at 90° to the warp; the weft strip a fold at 0°. The standard does not measure the
        bias: the twist stencils get its overall rigidity √(warp·weft), so the 45° fold is
        (√warp + √weft)²/4, and equal strips make the one isotropic rigidity."""
        return cls(fold_0=weft, fold_45=(math.sqrt(warp) + math.sqrt(weft)) ** 2 / 4,
                   fold_90=warp)

    def grid_rigidities(self) -> tuple[float, float, float]:
        """(B_uu, B_vv, B_uv): the rigidity of the grid's x_uu, x_vv and x_uv stencils whose
        energy ½(B_uu·K_xx² + B_vv·K_zz² + 2·B_uv·K_xz²) gives each fold its rigidity: a
        curvature κ along direction θ has K = κ·t·tᵀ, so a bias bend costs
        ½κ²·(B_uu + B_vv + 2·B_uv)/4."""
        b_uv = (4.0 * self.fold_45 - self.fold_0 - self.fold_90) / 2.0
        return self.fold_90, self.fold_0, b_uv

    def along(self, degrees: float) -> float:
        """The rigidity of a fold at `degrees` to the warp that this energy gives:
        curvature along θ = degrees + 90°, B(θ) = B_uu·c⁴ + B_vv·s⁴ + 2·B_uv·c²s²."""
        b_uu, b_vv, b_uv = self.grid_rigidities()
        t = math.radians(degrees + 90.0)
        c2, s2 = math.cos(t) ** 2, math.sin(t) ** 2
        return b_uu * c2 * c2 + b_vv * s2 * s2 + 2.0 * b_uv * c2 * s2
