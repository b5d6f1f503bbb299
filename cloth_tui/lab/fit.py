"""`cloth-tui lab fit`: a fabric from what its label and a ruler (or a textile lab's data
sheet) say, as a `[material]` section, and the lab's own tests run on it as the proof.

- areal density (g/m²): the label's, as it is;
- bending length c per direction (cm, ASTM D1388: half the overhang at the 41.5° line):
  B = ρ_A·g·c³, which the exact elastica holds to 0.02 % (peirce.py); two lengths (warp,
  weft) are written as `bending = [B_warp, B_weft]`, a fabric that bends by direction;
- an extension at a load from a strip test ("5 % at 10 N/5 cm"): stretch = (F/W)/ε, N/m;
- a Cusick drape coefficient: no closed form, so the shear stiffness, the one the
  measurements above leave free, is searched (regula falsi on log shear, a drape run each)
  until the lab's drape test gives it; a stiffer shear makes the disc drape less.

What was not measured (stretch, shear) comes from a preset, named in the notes. The proof:
the virtual Peirce test gives back each bending length (a strip cut along the warp, and one
along the weft), and the drape test the coefficient."""

from __future__ import annotations

import math
import re
from collections.abc import Callable
from dataclasses import dataclass

from .study import LabError

GRAVITY = 9.81
BASE_PRESET = "denim"       # what was not measured: a measured woven, the lab's default
PEIRCE_LINKS = 10           # the proof's strip: within 0.2 % of the elastica's B here
DRAPE_RESOLUTION = 25       # particles across the disc: the drape test's first default
BENDING_TOLERANCE = 0.02    # the proof's bound on each bending length, relative
DRAPE_TOLERANCE = 0.03      # the proof's bound on the drape coefficient, absolute
# The search stops nearer than the proof's bound, so that the proof (a run of the fabric as
# written, its numbers rounded) has room to spare.
DRAPE_AIM = 0.01
DRAPE_MAX_RUNS = 8
# Shear (N/m) the search may choose: from SHEAR_MIN, where a mid-weight disc already drapes
# to about a quarter (docs/lab.md), to the smaller stretch: a fabric stiffer in shear than in
# tension is none a drapemeter sees.
SHEAR_MIN = 0.05
DIGITS = 6                  # significant digits written

_NUMBER = r"[0-9]+(?:\.[0-9]*)?(?:[eE][-+]?[0-9]+)?|\.[0-9]+"
_LOAD = re.compile(rf"^\s*({_NUMBER})\s*N\s*/\s*({_NUMBER})?\s*(mm|cm|m)\s*$")
_WIDTH_UNIT = {"mm": 1e-3, "cm": 1e-2, "m": 1.0}


@dataclass(frozen=True)
class Measurements:
    areal_density: float                 # kg/m²
    bending_lengths: tuple[float, ...]   # m: (c,) or (warp, weft)
    stretch: tuple[float, float] | None  # N/m (warp, weft), from a strip test
    drape: float | None                  # the Cusick drape coefficient, 0–1
    base: str = BASE_PRESET              # the preset for what was not measured


def _positive(flag: str, text: str, what: str) -> float:
    try:
        v = float(text)
    except ValueError:
        v = math.nan
    if not math.isfinite(v) or v <= 0:
        raise LabError(f"{flag}: {text.strip()!r} is not {what}")
    return v


def parse_density(text: str) -> float:
    """--density in g/m² → kg/m²."""
    return _positive("--density", text, "a positive number of g/m² (e.g. 250)") / 1e3


def parse_bending_lengths(text: str) -> tuple[float, ...]:
    """--bending-length C or WARP,WEFT in cm → m."""
    parts = text.split(",")
    if len(parts) > 2:
        raise LabError(f"--bending-length: {text!r} has {len(parts)} values; give one length "
                       f"or warp,weft in cm (e.g. 2.4,1.9)")
    return tuple(_positive("--bending-length", p, "a positive length in cm (e.g. 2.4,1.9)")
                 / 100 for p in parts)


def parse_extension(text: str) -> tuple[float, float]:
    """--extension "E % at F N/W cm" (or "E,E % at …" for warp,weft) → stretch (N/m) per
    direction, (F/W)/ε: the tension per width over the strain."""
    example = "(e.g. \"5 % at 10 N/5 cm\", or \"5,8 % at 10 N/5 cm\" for warp,weft)"
    halves = re.split(r"\s+at\s+|\s*@\s*", text.strip(), maxsplit=1)
    if len(halves) != 2 or "%" not in halves[0]:
        raise LabError(f"--extension: {text!r} is not an extension at a load {example}")
    strains = [s.strip() for s in halves[0].replace("%", " ").split(",")]
    if len(strains) > 2:
        raise LabError(f"--extension: {len(strains)} extensions; give one, or warp,weft")
    strains = [_positive("--extension", s, f"an extension in % {example}") / 100
               for s in strains]
    if any(e >= 1 for e in strains):
        raise LabError(f"--extension: {text!r}: a strip test's extension is below 100 %")
    load = _LOAD.match(halves[1])
    if not load:
        raise LabError(f"--extension: {halves[1].strip()!r} is not a load per strip width "
                       f"{example}")
    force = _positive("--extension", load.group(1), f"a load in N {example}")
    width = _positive("--extension", load.group(2) or "1", f"a strip width {example}")
    tension = force / (width * _WIDTH_UNIT[load.group(3)])
    stretch = [tension / e for e in strains]
    return (stretch[0], stretch[-1])


def parse_drape(text: str) -> float:
    """--drape as 0–1 or a percentage ("45 %")."""
    s = text.strip()
    percent = s.endswith("%")
    v = _positive("--drape", s.rstrip("%").strip(), "a drape coefficient between 0 and 1 "
                                                    "(e.g. 0.45, or 45 %)")
    v = v / 100 if percent else v
    if v >= 1:
        raise LabError(f"--drape: {text.strip()!r} is not below 1: the drape coefficient is "
                       f"the share of the annulus the shadow covers (e.g. 0.45, or 45 %)")
    return v


def _round(v: float) -> float:
    return float(f"{v:.{DIGITS}g}")


def closed_form(m: Measurements) -> tuple[dict, list[str]]:
    """The [material] table the measurements give without a run, and where each value came
    from (a note per value not measured, or not held as measured). A LabError for what the
    material's keys refuse."""
    from ..materials.errors import MaterialError
    from ..materials.schema import material_from_table
    from .study import lab_material

    base = lab_material(m.base)
    rigidities = [_round(m.areal_density * GRAVITY * c ** 3) for c in m.bending_lengths]
    table = {"areal_density": _round(m.areal_density),
             "stretch": [_round(s) for s in (m.stretch or (base.stretch_warp,
                                                           base.stretch_weft))],
             "shear": _round(base.shear),
             "bending": rigidities if len(rigidities) == 2 else rigidities[0]}
    notes = []
    if len(m.bending_lengths) == 2:
        notes.append("bending by direction: [warp, weft]; the bias, which ASTM D1388 does "
                     "not measure, bends with their overall √(B_warp·B_weft)")
    if m.stretch is None:
        notes.append(f"stretch not measured: {m.base}'s at small strain, linear (give "
                     f"--extension)")
    if m.drape is None:
        notes.append(f"shear not measured: {m.base}'s (give --drape to fit it)")
    try:
        material_from_table(table, "material")
    except MaterialError as e:
        raise LabError(f"the measurements give no fabric the material can hold: {e}") from None
    return table, notes


def material_of(table: dict):
    from ..materials.schema import material_from_table
    return material_from_table(table, "material")


# --- the runs ----------------------------------------------------------------------------------


def peirce_bending_lengths(material, solver: str) -> list[dict]:
    """The virtual Peirce test on `material` at PEIRCE_LINKS, a strip cut along the warp
    (and along the weft, where the fabric bends by direction): each its direction, the
    overhang at the 41.5° line (m), half of it the bending length (m), and the runs of its
    search."""
    from .clamped import PEIRCE
    from .study import run

    out = []
    for case in run(PEIRCE, [PEIRCE_LINKS], material, solver=solver)["cases"]:
        (point,) = case["points"]
        out.append({"direction": case["params"]["direction"], "overhang": point["overhang"],
                    "bending_length": point["overhang"] / 2, "runs": point["runs"],
                    "wall_s": point["wall_s"]})
    return out


def drape_coefficient(material, resolution: int, solver: str) -> dict:
    """The lab's drape test on `material` at `resolution` particles across."""
    from .drape import DRAPE
    from .study import run

    (case,) = run(DRAPE, [resolution], material, solver=solver)["cases"]
    (point,) = case["points"]
    return {"drape": point["measured"], "folds": point["folds"], "wall_s": point["wall_s"]}


def _next_log_shear(points: list[tuple[float, float]], lo: float, hi: float) -> float | None:
    """The next ln(shear) to run from the runs so far, (ln shear, drape − aim): regula falsi
    inside the tightest bracket (kept off its ends, so a curved drape does not stall it),
    else a secant step (at least a factor 3, at most 30) towards the aim; None when the aim
    lies beyond the range's end already run."""
    below = [p for p in points if p[1] < 0]
    above = [p for p in points if p[1] > 0]
    if below and above:
        a, b = max(below, key=lambda p: p[1]), min(above, key=lambda p: p[1])
        x = a[0] - a[1] * (b[0] - a[0]) / (b[1] - a[1])
        lo_x, hi_x = sorted((a[0], b[0]))
        margin = 0.1 * (hi_x - lo_x)
        return min(max(x, lo_x + margin), hi_x - margin)
    x1, f1 = points[-1]
    direction = -1.0 if f1 > 0 else 1.0   # the drape grows with shear
    step = math.log(10)
    if len(points) > 1:
        x0, f0 = points[-2]
        if x1 != x0 and (f1 - f0) / (x1 - x0) > 0:
            step = min(max(abs(f1 * (x1 - x0) / (f1 - f0)), math.log(3)), math.log(30))
    x = min(max(x1 + direction * step, lo), hi)
    if any(abs(x - p[0]) < 1e-9 for p in points):
        return None
    return x


def fit_drape(table: dict, aim: float, resolution: int, solver: str,
              say: Callable[[str], None]) -> tuple[dict, list[dict]]:
    """The table with the shear whose drape coefficient is nearest `aim` within DRAPE_AIM
    (at most DRAPE_MAX_RUNS runs), and the runs: each its shear and drape coefficient."""
    lo, hi = math.log(SHEAR_MIN), math.log(max(min(table["stretch"]), SHEAR_MIN))
    x = min(max(math.log(table["shear"]), lo), hi)
    runs, points = [], []
    while x is not None and len(runs) < DRAPE_MAX_RUNS:
        trial = dict(table, shear=_round(math.exp(x)))
        say(f"drape run {len(runs) + 1} (at most {DRAPE_MAX_RUNS}): shear "
            f"{trial['shear']:.4g} N/m…")
        r = drape_coefficient(material_of(trial), resolution, solver)
        runs.append({"shear": trial["shear"], **r})
        say(f"  drape coefficient {r['drape']:.3f} (aim {aim:.3f}, {r['folds']} folds)")
        points.append((math.log(trial["shear"]), r["drape"] - aim))
        if abs(r["drape"] - aim) <= DRAPE_AIM:
            break
        x = _next_log_shear(points, lo, hi)
    best = min(runs, key=lambda r: abs(r["drape"] - aim))
    return dict(table, shear=best["shear"]), runs


def prove(material, m: Measurements, solver: str, drape_resolution: int,
          say: Callable[[str], None]) -> dict:
    """The lab's tests on the fabric as written: the virtual Peirce test's strips against
    the measured bending lengths (one, or warp and weft), and the drape test against a
    measured coefficient."""
    say(f"proof: virtual Peirce test ({PEIRCE_LINKS} links)…")
    strips = peirce_bending_lengths(material, solver)
    if len(strips) != len(m.bending_lengths):
        raise LabError(f"the virtual Peirce test cut {len(strips)} strips of a fabric measured "
                       f"in {len(m.bending_lengths)} directions")
    peirce = []
    for p, c in zip(strips, m.bending_lengths):
        error = p["bending_length"] / c - 1
        peirce.append({**p, "expected": c, "error": error, "tolerance": BENDING_TOLERANCE,
                       "ok": abs(error) <= BENDING_TOLERANCE})
        said = f" along the {p['direction']}" if len(strips) == 2 else ""
        say(f"  bending length{said} {p['bending_length'] * 100:.4g} cm (measured "
            f"{c * 100:.4g} cm, {error:+.2%})")
    out = {"peirce": peirce, "drape": None}
    if m.drape is not None:
        say(f"proof: drape test ({drape_resolution} particles across)…")
        d = drape_coefficient(material, drape_resolution, solver)
        out["drape"] = {**d, "expected": m.drape, "error": d["drape"] - m.drape,
                        "tolerance": DRAPE_TOLERANCE, "resolution": drape_resolution,
                        "ok": abs(d["drape"] - m.drape) <= DRAPE_TOLERANCE}
        say(f"  drape coefficient {d['drape']:.3f} (measured {m.drape:.3f})")
    out["ok"] = all(p["ok"] for p in peirce) and (out["drape"] is None or out["drape"]["ok"])
    return out
