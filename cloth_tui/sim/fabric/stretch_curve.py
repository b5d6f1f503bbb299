"""A measured fabric's stretch that stiffens with strain, on the model's structural edges.

An edge along x (z) stands for a strip of sheet of width w and rest length L; at strain ε it must
pull with the warp's (weft's) tension T(ε)·w (materials/measured.py). The solver keeps its distance
constraints C = |x_b − x_a| − L and gives each edge, before each substep's passes, the secant
compliance α = L/(w·S) with S = T(ε)/ε at the edge's strain now: once the strain holds still, the
constraint force S·w·ε is exactly the curve's tension, whatever the curve. The secant is relaxed
towards its target geometrically, S ← √(S·S(ε)): under a steady load a plain secant update is a
fixed-point iteration in log S whose factor, 1 − T′/S, reaches −1 where the tension grows as ε² (the
knits past their zero-strain sample); the half step makes it 1 − T′/(2S), inside (−1, 1) for any
tension that grows slower than ε⁴ (docs/physics.md, "Measured fabrics: stiffening and direction").
"""

from __future__ import annotations

import math
from dataclasses import dataclass

import numpy as np

from ...materials.schema import Material
from ..jit import kernel
from ..grid import Grid
from .material import ALONG_X, MIN_STIFFNESS, pair_kinds, strip_width


@dataclass(frozen=True)
class EdgeStretch:
    rest_over_width: np.ndarray  # (M,) L/w of each edge: α = (L/w)/S
    low: np.ndarray              # (M,) N/m, k at zero strain (warp's or weft's)
    high: np.ndarray             # (M,) N/m, k at strain `reach` and beyond
    reach: float


def edge_stretch(material: Material, grid: Grid, edges: np.ndarray) -> EdgeStretch | None:
    """Each structural edge's tension curve, or None for a material of linear stretch."""
    if material.stretch_curves is None:
        return None
    warp, weft = material.stretch_curves
    if warp.reach != weft.reach:
        raise ValueError("the warp's and weft's curves must reach their top sample together")
    kind, _, _ = pair_kinds(grid, edges)
    along_x = kind == ALONG_X
    rest = np.where(along_x, grid.dx, grid.dz)
    out = EdgeStretch(rest_over_width=rest / strip_width(grid, edges),
                      low=np.where(along_x, warp.low, weft.low),
                      high=np.where(along_x, warp.high, weft.high), reach=warp.reach)
    for arr in (out.rest_over_width, out.low, out.high):
        arr.setflags(write=False)
    return out


@kernel()
def relax_secant_compliance(x, edges, rest_length, rest_over_width, low, high, reach,
                            stiffness, alpha, relax):
    """For each edge: its strain now, the curve's secant S(ε) there, `stiffness` moved to
    √(stiffness·S(ε)) (without `relax`: set to S(ε)) and `alpha` = rest_over_width/stiffness
    (m/N)."""
    for e in range(edges.shape[0]):
        a = edges[e, 0]
        b = edges[e, 1]
        dx = x[b, 0] - x[a, 0]
        dy = x[b, 1] - x[a, 1]
        dz = x[b, 2] - x[a, 2]
        strain = math.sqrt(dx * dx + dy * dy + dz * dz) / rest_length[e] - 1.0
        if strain <= 0.0:
            target = low[e]
        else:
            s = min(strain / reach, 1.0)
            target = ((low[e] + (high[e] - low[e]) * s)
                      * (1.0 + strain) * (1.0 + 0.5 * strain))
        target = max(target, MIN_STIFFNESS)
        k = math.sqrt(stiffness[e] * target) if relax else target
        stiffness[e] = k
        alpha[e] = rest_over_width[e] / k


class StrainStiffening:
    """The secant stiffness of each edge (N/m, per unit width), carried from substep to
    substep; the first update takes the secant at the strain it finds (a sheet given a new
    fabric while stretched starts from the new fabric's tension there), later ones relax."""

    def __init__(self, stretch: EdgeStretch, edges: np.ndarray, rest_length: np.ndarray):
        self.stretch = stretch
        self.edges = np.ascontiguousarray(edges, dtype=np.int64)
        self.rest_length = np.ascontiguousarray(rest_length, dtype=np.float64)
        self.stiffness = np.maximum(stretch.low, MIN_STIFFNESS).astype(np.float64)
        self.alpha = stretch.rest_over_width / self.stiffness
        self._relax = False

    def compliance(self, x: np.ndarray) -> np.ndarray:
        """(M,) α (m/N) of each edge for positions x, after one relaxation step."""
        s = self.stretch
        relax_secant_compliance(x, self.edges, self.rest_length, s.rest_over_width, s.low,
                                s.high, s.reach, self.stiffness, self.alpha, self._relax)
        self._relax = True
        return self.alpha
