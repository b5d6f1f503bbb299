"""RunStats: what a run reports about itself (the status line, `simulate`, the wedge, the lab).

One frozen record with typed fields, so a reader names what it wants and a missing number is
a field's declared "not measured" value, never a key a reader guesses a default for. The
per-frame numbers are cheap; the others (stretch over every constraint, energy) are measured
only now and then (`measured`), and between, a snapshot carries the last full set refreshed
with the frame's own numbers (`refreshed`)."""

from __future__ import annotations

import dataclasses
import math
from dataclasses import dataclass

NAN = math.nan


@dataclass(frozen=True)
class FrameStats:
    """The numbers cheap enough for every frame."""
    frames: int = 0
    steps: int = 0                 # substeps taken by the state
    torn: int = 0                  # constraints broken (tearing.py)
    t: float = 0.0                 # simulated time, s
    recoveries: int = 0            # frames the divergence guard redid
    halted: str | None = None      # why stepping stopped, if it did
    frame_ms: float = 0.0          # simulation time of the last frame
    mean_frame_ms: float = 0.0
    step_ms: float = 0.0           # of one substep of the last frame
    substeps_used: int = 0         # adaptive or recovering: may differ from those asked
    wall_s: float = 0.0            # stepping only
    numerical_damping: float | None = None  # 1/s; None: not measurable
    # Whether the run meets its tolerances: adaptive, the controller's verdict on the last
    # frame; fixed substeps, the check of the last full statistics. None: nothing is bounded.
    tolerance_met: bool | None = None
    frame_error: float | None = None  # what the substep controller measured (adaptive only)


@dataclass(frozen=True)
class RunStats(FrameStats):
    """Every statistic of a run. The defaults read as "not measured": `RunStats()` is what a
    snapshot carries when nobody asked for the costly numbers (a bake)."""
    measured: bool = False         # the costly fields below were measured
    particles: int = 0
    constraints: int = 0
    finite: bool = True
    min_y: float = NAN
    max_speed: float = NAN
    max_stretch: float = NAN       # |L/L0 − 1| over the intact constraints
    mean_stretch: float = NAN
    solver: str = ""
    error: float | None = None     # solve error, share of L0; None: springs (no solve)
    error_tolerance: float | None = None  # None where there is no error to bound
    energy_tolerance: float | None = None
    energy: float | None = None    # J
    penetration: float = 0.0       # deepest a particle has been inside a collider, m
    effects: tuple[str, ...] = ()  # the step's stages, in order
    material: str | None = None    # the name of the scene's [material]; None: the original keys

    def __post_init__(self) -> None:
        # `finite` vouches for every measured number, not only the positions: an energy or
        # error gone NaN (a material at the edge of its range) makes the run not finite.
        if self.measured and self.finite and not all(
                v is None or math.isfinite(v) for v in
                (getattr(self, name) for name in MEASURED_NUMBERS)):
            object.__setattr__(self, "finite", False)

    def refreshed(self, frame: FrameStats) -> "RunStats":
        """These costly numbers with a later frame's cheap ones."""
        return dataclasses.replace(self, **_fields_of(frame, FrameStats))

    def as_dict(self) -> dict:
        """Plain values by name, for JSON and the `simulate` listing: a number that is not
        finite is None (JSON has no NaN or Infinity)."""
        out = {f.name: _plain(getattr(self, f.name)) for f in dataclasses.fields(self)}
        out["effects"] = list(self.effects)
        return out


# The physical numbers `finite` vouches for (the timings are the clock's, never NaN)
MEASURED_NUMBERS = ("min_y", "max_speed", "max_stretch", "mean_stretch", "error", "energy",
                    "penetration", "numerical_damping", "frame_error")


def _plain(value):
    if isinstance(value, float) and not math.isfinite(value):
        return None
    return value


def _fields_of(obj, cls) -> dict:
    return {f.name: getattr(obj, f.name) for f in dataclasses.fields(cls)}
