"""The Peirce cantilever test (ASTM D1388 option A, ISO 9073-7): a strip is slid over the
edge of a platform until the line from the edge to its tip falls 41.5° below horizontal;
the overhang O then gives the bending length c = O/2 and the rigidity B = ρ_A·g·c³.
The 41.5° is chosen so that c = O/2 holds for the exact elastica; `overhang` computes the
overhang a fabric of rigidity B really shows, from the elastica."""

from __future__ import annotations

import functools
import math

from .elastica import load_for_chord_angle

PEIRCE_ANGLE = math.radians(41.5)


def peirce_rigidity(areal_density: float, overhang: float, gravity: float = 9.81) -> float:
    """N·m: the standard's B = ρ_A·g·(O/2)³."""
    return areal_density * gravity * (overhang / 2) ** 3


@functools.cache
def peirce_load() -> float:
    """wL³/B of the strip whose tip line is at 41.5°: 8.004 (the standard's O/2 rule
    assumes exactly 8)."""
    return load_for_chord_angle(PEIRCE_ANGLE)


def overhang(bending: float, areal_density: float, gravity: float = 9.81) -> float:
    """m: the overhang at which a strip of rigidity B and areal density ρ_A shows the 41.5°
    line: L with ρ_A·g·L³/B = peirce_load()."""
    return math.cbrt(peirce_load() * bending / (areal_density * gravity))
