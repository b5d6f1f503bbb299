"""Accuracy the user sets: substeps chosen so that a frame's solve error (and, if asked, the
run's numerical damping) stays within a tolerance.

The error measure is the frame's solve error e = max |C + α̃λ|/L0 (measures.solve_error: how
far the frame ends from the material's own equilibrium; for pbd the stretch |L/L0 − 1|), the
step control is the number of substeps, as in an adaptive ODE solver (Macklin et al. 2019,
"Small steps": the error left by a fixed number of passes falls about as h²):

- a frame whose error e exceeds the tolerance τ is redone with
  n' = ⌈n · √(e/τ) · SAFETY⌉ substeps (at least n + 1, at most MAX_RAISE·n, never above the
  cap), until it meets τ or runs at the cap; at the cap it is accepted and reported unmet;
- after SLACK_FRAMES frames in a row without a change, the count is lowered to what the
  worst error e_w of those frames predicts, ⌈n · √(e_w · SAFETY/τ)⌉ (at most halved, never
  below the scene's own `substeps`). It aims at τ/SAFETY, and the window and that margin
  together keep the count from oscillating (at worst one redo per window).

With an energy tolerance τ_E, the numerical damping d (the share of the sheet's free energy
lost per second that no damping key asked for; the runner measures it per frame) is bounded
too. One frame's d is not a measure of the step: a swing trades kinetic for potential
energy, and the last substep's velocity misreads the kinetic part by ± a large share, so
the control acts on means over several frames, and redoes nothing (the energy a frame lost
is not the frame's error alone). Energy made (d < 0, a second-order step whose solve stops
early) is bounded as energy lost is, by |d̄|:

- when the mean over the last ENERGY_FRAMES of those frames exceeds τ_E, the next frames
  get n' = ⌈n · d̄ · ENERGY_SAFETY/τ_E⌉ with d̄ that recent mean (at least n + 1, at most
  MAX_RAISE·n, never above the cap): a burst is met within a few frames, where the mean
  since the last change would take as long to rise as the quiet frames before it; d
  falls about as h (measured on a swinging sheet: roughly as n^−0.8), so taking it as order
  1 raises a little more than needed rather than less. A raise keeps the recent frames' d
  as the new count would have had them, d·n/n' (d ∝ h), so a burst that goes on raises again
  at the next frame; a lowering, and a frame whose d is not measured (a contact, a tear),
  start the recent frames afresh;
- the lowering above also keeps n · d̄ · ENERGY_SAFETY/τ_E, d̄ the mean since the count last
  changed, and waits ENERGY_SLACK_FRAMES instead:
  the damping comes in bursts (a swing's free edge whipping round), which a quiet
  half-second does not foresee.

A solver whose solve, stopped early, can make energy its error does not see (lbfgs:
`SolverBase.bounds_energy_made`) has energy made bounded with no energy tolerance set, by
ENERGY_MADE_TOLERANCE, as above. Implicit Euler solved to convergence makes none, so energy
made is the solve's error at any tolerance: the hanging strip swinging at the default scene's
1 substep of 2 iterations reads a solve error of 0.014 against τ = 0.05 while its swing grows
from 22 to 40 mm in 4 periods (period +6.6 %). The bound sits above what a healthy swing
misreads (the default scene's 6-frame means reach −0.17/s at 17–129 cells) and below a solve
that makes energy (that scene at 4 iterations: −0.14/s median, −0.55/s at the 5th percentile).

Plain Python, no kernels: the runner measures e and d and asks.
"""

from __future__ import annotations

import math
from dataclasses import dataclass, field

SAFETY = 1.25      # aim a little under the tolerance, so a raised frame rarely needs a redo
MAX_RAISE = 4      # at most ×4 substeps per redo: a single wild frame cannot jump to the cap
SLACK_FRAMES = 30  # frames in a row without a change before lowering (0.5 s at 60 Hz)
ENERGY_FRAMES = 6  # frames of numerical damping averaged before the count is raised for it
# Numerical damping is aimed at τ_E/ENERGY_SAFETY: its bursts (below) overshoot a mean that
# was just met.
ENERGY_SAFETY = 2.0
# With an energy tolerance, frames without a change before lowering (2 s at 60 Hz): numerical
# damping comes in bursts (a swing's free edge whipping round loses more in a few frames
# than the quiet half-second before it), so a quiet window predicts too few substeps.
ENERGY_SLACK_FRAMES = 120
ENERGY_MADE_TOLERANCE = 0.25  # 1/s: energy made, bounded by default where the solver asks


@dataclass
class SubstepController:
    tolerance: float        # τ on the solve error, share of rest length
    floor: int              # the scene's substeps: never fewer
    cap: int                # never more
    adaptive: bool = True   # False: report whether the tolerances are met, change nothing
    energy_tolerance: float | None = None  # τ_E on numerical damping, 1/s; None: unbounded
    made_tolerance: float | None = None    # bound on energy made alone, 1/s (module docstring)
    substeps: int = 0       # current count (the floor until the first raise)
    met: bool = True        # whether the last accepted frame met the tolerances
    slack_frames: int = 0   # frames since the count last changed
    window_error: float = 0.0    # worst error over those frames
    damping_sum: float = 0.0     # Σ d over those of them where it was measured
    damping_frames: int = 0      # how many they are
    recent: list = field(default_factory=list)  # d of the last ENERGY_FRAMES of them

    def __post_init__(self) -> None:
        self.cap = max(self.cap, self.floor)
        self.substeps = self.substeps or self.floor

    @property
    def mean_damping(self) -> float | None:
        """d̄ over the frames since the count last changed (None: none measured)."""
        return self.damping_sum / self.damping_frames if self.damping_frames else None

    def _energy_need(self, margin: float = 1.0, recent: bool = False) -> float:
        """|d̄|·margin/τ_E: the factor on the substeps that meets τ_E/margin (0: unbounded),
        d̄ the mean since the count last changed, or with `recent` over the last
        ENERGY_FRAMES frames (0 until there are so many). Energy made (d̄ < 0: a
        second-order step whose solve stops early) is bounded as energy lost is: both are
        the step's error."""
        d = self.mean_damping
        if recent:
            d = (sum(self.recent) / len(self.recent)
                 if len(self.recent) >= ENERGY_FRAMES else None)
        if d is None:
            return 0.0
        need = 0.0
        if self.energy_tolerance is not None:
            need = _ratio(abs(d) * margin, self.energy_tolerance)
        if self.made_tolerance is not None and d < 0.0:
            need = max(need, _ratio(-d * margin, self.made_tolerance))
        return need

    def _error_need(self, error: float, margin: float = 1.0) -> float:
        return math.sqrt(_ratio(max(error, 0.0) * margin, self.tolerance))

    def meets(self, error: float) -> bool:
        """Whether a frame of this error meets τ, and the recent mean damping τ_E."""
        return self._error_need(error) <= 1.0 and self._energy_need() <= 1.0

    def _set(self, substeps: int, carry: bool = False) -> None:
        if carry:  # a raise: a burst that goes on is met at once, not ENERGY_FRAMES later
            # the recent frames' damping as the new count would have had it (d ∝ h)
            self.recent[:] = [d * self.substeps / substeps for d in self.recent]
        else:  # (a lowering carried over would read as a burst and raise straight back)
            self.recent.clear()
        self.substeps = substeps
        self.slack_frames = self.damping_frames = 0
        self.window_error = self.damping_sum = 0.0

    def _raised(self, need: float) -> int:
        factor = min(MAX_RAISE, need * SAFETY)
        return min(self.cap, max(self.substeps + 1, math.ceil(self.substeps * factor)))

    def redo_with(self, error: float) -> int | None:
        """After a frame of solve error `error`: the substeps to redo it with, or None to
        accept it as it is (it met τ, or no more substeps are allowed)."""
        need = self._error_need(error)
        if need <= 1.0 or not self.adaptive or self.substeps >= self.cap:
            return None
        self._set(self._raised(need), carry=True)
        return self.substeps

    def accept(self, error: float, damping: float | None = None) -> int:
        """Record an accepted frame and its numerical damping (1/s, None if not measured);
        returns the substeps for the next frame."""
        if damping is not None:
            self.damping_sum += damping
            self.damping_frames += 1
            self.recent.append(damping)
            del self.recent[:-ENERGY_FRAMES]
        else:  # (a contact, a tear: the frames before it are no longer recent)
            self.recent.clear()
        self.met = self.meets(error)
        if not self.adaptive:
            return self.substeps
        self.slack_frames += 1
        self.window_error = max(self.window_error, error)
        if self._energy_need(recent=True) > 1.0 and self.substeps < self.cap:
            self._set(self._raised(self._energy_need(ENERGY_SAFETY, recent=True) / SAFETY),
                      carry=True)
        elif self.slack_frames >= (SLACK_FRAMES if self.energy_tolerance is None
                                   else ENERGY_SLACK_FRAMES):
            need = max(self._error_need(self.window_error, SAFETY),
                       self._energy_need(ENERGY_SAFETY))
            want = math.ceil(self.substeps * min(need, self.cap))  # (an unmeetable need: inf)
            self._set(max(self.floor, want, self.substeps // 2)
                      if want < self.substeps else self.substeps)
        return self.substeps


def _ratio(amount: float, tolerance: float) -> float:
    """amount/tolerance, where a tolerance that underflowed to 0 (a tear strength of 5e-324
    N/m makes one) is met only by nothing: inf for any amount, 0 for none."""
    if tolerance > 0.0:
        return amount / tolerance  # (a float overflows to inf, never raises)
    return math.inf if amount > 0.0 else 0.0
