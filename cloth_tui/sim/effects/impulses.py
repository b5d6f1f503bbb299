"""Impulses applied once per frame, before the substeps: rain.

A drop displaces the particle it strikes downward by `rain_strength` and its grid neighbours
less, with a Gaussian falloff w = exp(−(Δi² + Δj²)/RAIN_RADIUS²) over grid distance, and
gives each displaced particle the velocity of moving that far in one frame (v += Δx/frame_dt),
so the position-based step (which reads velocities) keeps the motion: the same rule as
Simulation.bump. The number of drops in a frame is Poisson with mean rain_rate·frame_dt, and
both the count and the struck particles come from a generator seeded by (behavior.seed, frame
index): the rain is a function of the seed and the time alone, identical after a pipeline
rebuild or a recovered frame.
"""

from __future__ import annotations

import numpy as np

from ..jit import kernel
from ..params import StepParams

RAIN_RADIUS = 1.5  # grid spacings: e-folding distance of the falloff
RAIN_REACH = 3     # grid spacings: farthest neighbour a drop moves (w(3) ≈ 2 %)


@kernel()
def apply_raindrop(x, v, inv_mass, nx, nz, particle, depth, inv_dt, inv_r2, reach):
    """Displace `particle` of the nz-row, nx-column grid down by `depth` and its neighbours
    less, with matching velocity."""
    i0 = particle // nx
    j0 = particle % nx
    for i in range(max(0, i0 - reach), min(nz, i0 + reach + 1)):
        for j in range(max(0, j0 - reach), min(nx, j0 + reach + 1)):
            p = i * nx + j
            if inv_mass[p] == 0.0:
                continue
            dy = -depth * np.exp(-((i - i0) ** 2 + (j - j0) ** 2) * inv_r2)
            x[p, 1] += dy
            v[p, 1] += dy * inv_dt


class Rain:
    name = "rain"

    def __init__(self, model, params: StepParams, seed: int):
        self.nx, self.nz, self.inv_mass = model.nx, model.nz, model.inv_mass
        self.params, self.seed = params, seed
        self.drops = 0  # struck so far (for tests and stats)

    def strikes(self, t: float, frame_dt: float) -> np.ndarray:
        """Indices of the particles struck in the frame starting at time t."""
        frame = int(round(t / frame_dt))
        rng = np.random.default_rng([self.seed, frame])
        k = rng.poisson(self.params.rain_rate * frame_dt)
        return rng.integers(0, self.nx * self.nz, size=k)

    def apply(self, state, frame_dt):
        struck = self.strikes(state.t, frame_dt)
        for p in struck:
            apply_raindrop(state.x, state.v, self.inv_mass, self.nx, self.nz, int(p),
                           self.params.rain_strength, 1.0 / frame_dt, 1.0 / RAIN_RADIUS ** 2,
                           RAIN_REACH)
        self.drops += len(struck)


def build_impulses(scene, model, params: StepParams) -> list:
    f = scene.forces
    if f.rain and f.rain_strength > 0 and f.rain_rate > 0:
        return [Rain(model, params, scene.behavior.seed)]
    return []
