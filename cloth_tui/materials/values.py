"""The material's numeric keys: unit, allowed range, meaning, and the check of one value
(shared by the [material] section and the preset table)."""

from __future__ import annotations

from dataclasses import dataclass
from typing import Any

from ..user_values import finite_float, short_repr
from .errors import MaterialError


@dataclass(frozen=True)
class KeySpec:
    unit: str
    lo: float
    hi: float
    lo_open: bool
    doc: str


# Wide enough for any fabric, film or leather (the table spans 50–800 g/m², 1.5–1700 µN·m),
# narrow enough to refuse what no sheet is: the upper bounds are not physical limits.
KEYS: dict[str, KeySpec] = {
    "areal_density": KeySpec("kg/m²", 0.0, 100.0, True,
                             "mass per unit area; the sheet's mass is density × area"),
    "stretch": KeySpec("N/m", 0.0, 1e7, True,
                       "tensile stiffness: tension per unit width per unit strain; one number "
                       "or [warp, weft] (warp along x, weft along z)"),
    "shear": KeySpec("N/m", 0.0, 1e7, True,
                     "in-plane shear stiffness: shear force per unit length per radian"),
    "bending": KeySpec("N·m", 0.0, 10.0, False,
                       "bending rigidity B: moment per unit width per unit curvature; one "
                       "number or [warp, weft]: the rigidity of a strip cut along the warp "
                       "(bending along x) and of one cut along the weft (along z), as ASTM "
                       "D1388 measures them"),
    "damping": KeySpec("1/s", 0.0, 1e3, False,
                       "viscous drag per unit mass: velocities decay as exp(−damping·t), "
                       "independent of timestep and substeps"),
    "tear_strength": KeySpec("N/m", 0.0, 1e7, True,
                             "tension per unit width at which the fabric tears, with "
                             "behavior.tear (optional: without it, tear_stretch)"),
    "tear_length": KeySpec("m", 0.0, 1.0, False,
                           "the width across which the tension is averaged before it is "
                           "compared with tear_strength (a few yarns; a grid coarser than it "
                           "judges each edge alone)"),
}
DEFAULT_TEAR_LENGTH = 0.005  # m: a few yarns of a woven (0.2–1 mm apart)


def describe(name: str) -> str:
    s = KEYS[name]
    lo = f"{s.lo:g} {'<' if s.lo_open else '≤'} value ≤ {s.hi:g}"
    if name == "stretch":
        return f"a number or [warp, weft] of numbers with {lo} ({s.unit})"
    if name == "bending":
        return (f"a number with {lo}, or [warp, weft] of numbers with 0 < value ≤ {s.hi:g} "
                f"({s.unit})")
    return f"a number with {lo} ({s.unit})"


def number(name: str, value: Any, where: str) -> float:
    def bad(reason: str = "") -> MaterialError:
        return MaterialError(f"{where}.{name} = {short_repr(value)} is not allowed"
                             f"{': ' + reason if reason else ''}; expected {describe(name)}")

    if isinstance(value, bool) or not isinstance(value, (int, float)):
        raise bad()
    v = finite_float(value)
    if v is None:
        raise bad("not a finite number")
    s = KEYS[name]
    if v < s.lo or (s.lo_open and v == s.lo) or v > s.hi:
        raise bad()
    return v


def bending_pair(value: Any, where: str) -> tuple[float, float] | None:
    """`bending` as (warp, weft) when given as a list, None for one number. A strip that
    does not bend at all has no place beside one that does: both must be positive."""
    if not isinstance(value, (list, tuple)):
        return None
    if len(value) != 2:
        raise MaterialError(f"{where}.bending = {short_repr(value)} is not allowed: a list "
                            f"must be [warp, weft]; expected {describe('bending')}")
    warp, weft = number("bending", value[0], where), number("bending", value[1], where)
    if warp == 0.0 or weft == 0.0:
        raise MaterialError(f"{where}.bending = {short_repr(value)} is not allowed: a "
                            f"[warp, weft] pair needs both positive (bending = 0 for none); "
                            f"expected {describe('bending')}")
    return warp, weft


def stretch_pair(value: Any, where: str) -> tuple[float, float]:
    """`stretch` as (warp, weft): one number is both."""
    if isinstance(value, (list, tuple)):
        if len(value) != 2:
            raise MaterialError(f"{where}.stretch = {short_repr(value)} is not allowed: a list "
                                f"must be [warp, weft]; expected {describe('stretch')}")
        return number("stretch", value[0], where), number("stretch", value[1], where)
    v = number("stretch", value, where)
    return v, v
