"""What is reported about a state: stretch and energy, for the runner, the app and the
accuracy study alike.

Stretch of a constraint is |L/L0 − 1|. Torn constraints (state.alive == 0, tearing.py) are
left out of every measure: they hold no energy and their length is a gap, not a stretch. Energy is kinetic + gravitational (height from y = 0)
+ elastic, the elastic part from the solver's own force estimate:

    springs  ½ k (L − L0)² per spring (the force the integrator uses)
    xpbd     ½ α f² per constraint with f = λ/h², λ the multiplier of the last substep
             (Macklin et al. 2016): at convergence f = −C/α and this equals C²/(2α), but an
             unconverged solve leaves a residual C the constraint never pushed against, and
             C²/(2α) would count it as stored energy (with α = 1e-8 m/N, kilojoules)
    pbd      none: rigid constraints store no energy

The residual of xpbd, max |C + α̃λ| over the constraints (α̃ = α/h²), is reported apart as
`constraint_error` (m): how far the solve is from the compliant equilibrium it aims at.
Kernels here keep IEEE semantics (no fastmath) because a NaN must show as NaN.
"""

from __future__ import annotations

import math

import numpy as np

from ..scene import Scene
from .jit import kernel
from .model import ClothModel
from .state import ClothState


@kernel(fastmath=False, inline="always")
def edge_length(x, edges, e) -> float:
    """|x_b − x_a| of constraint e, m."""
    a = edges[e, 0]
    b = edges[e, 1]
    dx = x[b, 0] - x[a, 0]
    dy = x[b, 1] - x[a, 1]
    dz = x[b, 2] - x[a, 2]
    return math.sqrt(dx * dx + dy * dy + dz * dz)


@kernel(fastmath=False)
def max_stretch(x, edges, rest, alive) -> float:
    """max |L/L0 − 1| over the intact constraints; NaN if any length is NaN. One pass, no
    temporary arrays: cheap enough to run after every frame for the substep controller."""
    worst = 0.0
    for e in range(edges.shape[0]):
        if not alive[e]:
            continue
        s = abs(edge_length(x, edges, e) / rest[e] - 1.0)
        if s != s:
            return s
        if s > worst:
            worst = s
    return worst


@kernel(fastmath=False)
def all_finite(x, v) -> bool:
    """Every position and velocity finite. One pass, no temporary arrays: the runner's check
    of every frame (NumPy's isfinite(...).all() allocates two per-particle masks; a masked
    check took 0.75 ms at 128², 12 % of the frame)."""
    for i in range(x.shape[0]):
        for k in range(3):
            if not (math.isfinite(x[i, k]) and math.isfinite(v[i, k])):
                return False
    return True


@kernel(fastmath=False)
def spring_energy(x, edges, rest, alive, k) -> float:
    """Σ ½ k (L − L0)² over the intact constraints, J."""
    total = 0.0
    for e in range(edges.shape[0]):
        if not alive[e]:
            continue
        c = edge_length(x, edges, e) - rest[e]
        total += 0.5 * k * c * c
    return total


@kernel(fastmath=False)
def xpbd_residual(x, edges, rest, alive, lambdas, alpha_tilde) -> float:
    """max |C + α̃λ| over the intact constraints, m (0 when the compliant solve converged)."""
    worst = 0.0
    for e in range(edges.shape[0]):
        if not alive[e]:
            continue
        # λ is accumulated with C = L0 − L in the projection (xpbd.py), hence the signs
        r = abs(rest[e] - edge_length(x, edges, e) - alpha_tilde * lambdas[e])
        if r > worst:
            worst = r
    return worst


def stretch(model: ClothModel, x: np.ndarray, alive: np.ndarray | None = None
            ) -> tuple[float, float]:
    """Max and mean of |L/L0 − 1| over the enabled constraints still intact (all of them
    when `alive` is None). NaN if a position is NaN."""
    if alive is None:
        alive = np.ones(model.num_constraints, np.uint8)
    return _stretch_max_mean(x, model.edges, model.rest_length, alive)


@kernel(fastmath=False)
def _stretch_max_mean(x, edges, rest, alive):
    """One pass, no temporaries: at 256² the NumPy version's gathers took ~6 % of the
    simulation thread (the app asks every 0.2 s)."""
    worst = 0.0
    total = 0.0
    count = 0
    for e in range(edges.shape[0]):
        if not alive[e]:
            continue
        r = abs(edge_length(x, edges, e) / rest[e] - 1.0)
        if r > worst or r != r:  # a NaN is kept, as np.max keeps it
            worst = r
        total += r
        count += 1
    if count == 0:
        return 0.0, 0.0
    return worst, total / count


def kinetic_energy(model: ClothModel, state: ClothState) -> float:
    """½ Σ m v², J."""
    return 0.5 * float(np.dot(model.mass, np.einsum("ij,ij->i", state.v, state.v)))


def gravitational_energy(model: ClothModel, state: ClothState, scene: Scene) -> float:
    """Σ m g y (height from y = 0), J; 0 without gravity."""
    if not scene.forces.gravity:
        return 0.0
    return scene.forces.gravity_strength * float(np.dot(model.mass, state.x[:, 1]))


def elastic_energy(model: ClothModel, state: ClothState, scene: Scene,
                   lambdas: np.ndarray | None = None, h: float = 0.0) -> float:
    """Elastic energy by the solver's force estimate (module docstring), J. For xpbd,
    `lambdas` are the last substep's multipliers and `h` its length; without them (before
    any substep) the constraints have exerted no force yet."""
    b = scene.behavior
    if not model.num_constraints:
        return 0.0
    if b.solver == "springs":
        return float(spring_energy(state.x, model.edges, model.rest_length, state.alive,
                                   b.stiffness))
    if b.solver == "xpbd" and lambdas is not None and h > 0.0:
        f = lambdas / (h * h)
        return 0.5 * b.compliance * float(np.dot(f, f))
    return 0.0


def energy(model: ClothModel, state: ClothState, scene: Scene,
           lambdas: np.ndarray | None = None, h: float = 0.0) -> float:
    """Kinetic + gravitational + elastic energy, J."""
    return (kinetic_energy(model, state) + gravitational_energy(model, state, scene)
            + elastic_energy(model, state, scene, lambdas, h))


def constraint_error(model: ClothModel, state: ClothState, scene: Scene,
                     lambdas: np.ndarray | None, h: float) -> float | None:
    """xpbd only: max |C + α̃λ| (m), the part of the constraint error that the elastic energy
    above leaves out. None for the other solvers or before any substep."""
    if scene.behavior.solver != "xpbd" or lambdas is None or h <= 0.0 \
            or not model.num_constraints:
        return None
    alpha_tilde = scene.behavior.compliance / (h * h)
    return float(xpbd_residual(state.x, model.edges, model.rest_length, state.alive, lambdas,
                               alpha_tilde))
