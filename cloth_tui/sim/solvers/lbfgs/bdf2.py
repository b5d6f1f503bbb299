"""BDF2, the second-order backward difference, as lbfgs's prediction and velocity stages:

    x⁺ − x̂ = (2h/3)·v⁺,   v⁺ − v̂ = (2h/3)·a(x⁺),   x̂ = (4xₙ − xₙ₋₁)/3,  v̂ = (4vₙ − vₙ₋₁)/3

so x⁺ is implicit Euler's minimum over a step of h' = 2h/3 from the prediction
y = x̂ + h'·v̂ + h'²·a_ext, and the solve stage (solver.py) is the same minimisation with h'.
Like implicit Euler it damps what the substep cannot resolve (ωh ≫ 1), but a motion it
resolves loses energy at about (ωh)⁴ per step where implicit Euler loses (ωh)², so a swing
loses less at the same substeps (docs/physics.md, lbfgs).

The past (xₙ₋₁, vₙ₋₁) is the last substep's, where nothing moved the sheet since (a new
step, a redone frame, a push or a pin start from a past of constant velocity, xₙ₋₁ =
xₙ − h·vₙ, vₙ₋₁ = vₙ: a sheet at rest stays at rest)."""

from __future__ import annotations

import math

import numpy as np

from ...jit import kernel
from ...params import StepParams
from ..xpbd.verlet import IntegrateVerlet, update_velocities

STEP_SHARE = 2.0 / 3.0  # h'/h


@kernel()
def predict_bdf2(x, x_prev, v, v_past, x_past, accel, inv_mass, h, keep, max_speed, base):
    """x_prev ← x; base ← x̂; x ← x̂ + keep·h'·v̂ + h'²·a (module docstring), the step from
    xₙ clamped to max_speed·h as integrate_verlet clamps it; accel ← 0."""
    hs = STEP_SHARE * h
    max_step = max_speed * h
    for i in range(x.shape[0]):
        for k in range(3):
            x_prev[i, k] = x[i, k]
        if inv_mass[i] == 0.0:
            for k in range(3):
                base[i, k] = x[i, k]
                accel[i, k] = 0.0
            continue
        dx = _move(x, x_past, v, v_past, accel, base, i, 0, keep, hs)
        dy = _move(x, x_past, v, v_past, accel, base, i, 1, keep, hs)
        dz = _move(x, x_past, v, v_past, accel, base, i, 2, keep, hs)
        d2 = dx * dx + dy * dy + dz * dz
        s = 1.0
        if d2 > max_step * max_step:
            s = max_step / math.sqrt(d2)
        x[i, 0] += s * dx
        x[i, 1] += s * dy
        x[i, 2] += s * dz
        accel[i, 0] = 0.0
        accel[i, 1] = 0.0
        accel[i, 2] = 0.0


@kernel(inline="always")
def _move(x, x_past, v, v_past, accel, base, i, k, keep, hs) -> float:
    """base[i, k] ← x̂; returns y − xₙ along k."""
    xh = (4.0 * x[i, k] - x_past[i, k]) / 3.0
    vh = (4.0 * v[i, k] - v_past[i, k]) / 3.0
    base[i, k] = xh
    return xh - x[i, k] + vh * keep * hs + accel[i, k] * hs * hs


class PredictBDF2(IntegrateVerlet):
    """The prediction (module docstring); keeps the past it needs."""

    name = "predict_bdf2"

    def __init__(self, model, params: StepParams):
        super().__init__(model, params)
        n = model.num_particles
        self.free = model.inv_mass > 0
        self.base = np.zeros((n, 3))     # x̂, which the velocity stage reads
        self._x_past = np.zeros((n, 3))  # xₙ₋₁
        self._v_past = np.zeros((n, 3))  # vₙ₋₁
        self._x_end = np.full((n, 3), np.nan)  # where the last substep left the sheet
        self._v_end = np.full((n, 3), np.nan)
        self._x_start = np.zeros((n, 3))  # this substep's xₙ, vₙ: the next one's past
        self._v_start = np.zeros((n, 3))

    def _past_holds(self, state) -> bool:
        f = self.free
        return (np.array_equal(state.x[f], self._x_end[f])
                and np.array_equal(state.v[f], self._v_end[f]))

    def apply(self, state, h):
        if not self._past_holds(state):
            np.subtract(state.x, h * state.v, out=self._x_past)
            self._v_past[...] = state.v
        else:
            self._x_past[...] = self._x_start
            self._v_past[...] = self._v_start
        self._x_start[...] = state.x
        self._v_start[...] = state.v
        predict_bdf2(state.x, state.x_prev, state.v, self._v_past, self._x_past, state.accel,
                     self.inv_mass, h, self.keep(h), self.params.max_speed, self.base)

    def ended(self, state) -> None:
        """The substep is over: where it left the sheet, to know the next one follows it."""
        self._x_end[...] = state.x
        self._v_end[...] = state.v


class VelocitiesBDF2:
    """v⁺ = (x⁺ − x̂)/h' (module docstring), clamped as update_velocities clamps; a held
    particle keeps the speed its pin drives it at, (x⁺ − xₙ)/h."""

    name = "update_velocities_bdf2"

    def __init__(self, model, params: StepParams, predict: PredictBDF2):
        self.inv_mass = model.inv_mass
        self.held = np.flatnonzero(model.inv_mass == 0)
        self.params = params
        self.predict = predict

    def apply(self, state, h):
        update_velocities(state.x, self.predict.base, state.v, self.inv_mass,
                          1.0 / (STEP_SHARE * h), self.params.max_speed)
        held = self.held
        state.v[held] = (state.x[held] - state.x_prev[held]) / h
        self.predict.ended(state)
