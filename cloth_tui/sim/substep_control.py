"""Accuracy the user sets: substeps chosen so that a frame's stretch stays within a tolerance.

The error measure is the frame's max stretch |L/L0 − 1| (the visible error of a position-based
solve), the step control is the number of substeps, as in an adaptive ODE solver (Macklin
et al. 2019, "Small steps": the stretch left by a fixed number of passes falls about as h²):

- a frame whose max stretch s exceeds the tolerance τ is redone with
  n' = ⌈n · √(s/τ) · SAFETY⌉ substeps (at least n + 1, at most MAX_RAISE·n, never above the
  cap), until it meets τ or runs at the cap; at the cap it is accepted and reported unmet;
- after SLACK_FRAMES frames in a row without a redo, the count is lowered to what the worst
  stretch s_w of those frames predicts, ⌈n · √(s_w · SAFETY/τ)⌉ (at most halved, never below
  the scene's own `substeps`). It aims at τ/SAFETY, and the window and that margin together
  keep the count from oscillating (at worst one redo per window).

Plain Python, no kernels: the runner measures s and asks.
"""

from __future__ import annotations

import math
from dataclasses import dataclass

SAFETY = 1.25      # aim a little under the tolerance, so a raised frame rarely needs a redo
MAX_RAISE = 4      # at most ×4 substeps per redo: a single wild frame cannot jump to the cap
SLACK_FRAMES = 30  # frames in a row without a redo before lowering (0.5 s at 60 Hz)


@dataclass
class SubstepController:
    tolerance: float        # τ, share of rest length
    floor: int              # the scene's substeps: never fewer
    cap: int                # never more
    adaptive: bool = True   # False: report whether τ is met, change nothing
    substeps: int = 0       # current count (the floor until the first raise)
    met: bool = True        # whether the last accepted frame met τ
    slack_frames: int = 0   # frames since the last raise or lowering
    window_stretch: float = 0.0  # worst stretch over those frames

    def __post_init__(self) -> None:
        self.cap = max(self.cap, self.floor)
        self.substeps = self.substeps or self.floor

    def redo_with(self, stretch: float) -> int | None:
        """After a frame of max stretch `stretch`: the substeps to redo it with, or None to
        accept it as it is (it met τ, or no more substeps are allowed)."""
        if stretch <= self.tolerance or not self.adaptive or self.substeps >= self.cap:
            return None
        factor = min(MAX_RAISE, math.sqrt(stretch / self.tolerance) * SAFETY)
        self.substeps = min(self.cap, max(self.substeps + 1, math.ceil(self.substeps * factor)))
        self.slack_frames = 0
        self.window_stretch = 0.0
        return self.substeps

    def accept(self, stretch: float) -> int:
        """Record an accepted frame; returns the substeps for the next frame."""
        self.met = stretch <= self.tolerance
        if not self.adaptive:
            return self.substeps
        self.slack_frames += 1
        self.window_stretch = max(self.window_stretch, stretch)
        if self.slack_frames >= SLACK_FRAMES:
            want = math.ceil(self.substeps
                             * math.sqrt(self.window_stretch * SAFETY / self.tolerance))
            if want < self.substeps:
                self.substeps = max(self.floor, want, self.substeps // 2)
            self.slack_frames = 0
            self.window_stretch = 0.0
        return self.substeps
