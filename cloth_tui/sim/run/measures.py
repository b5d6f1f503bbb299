"""What is reported about a state: stretch and energy, for the runner, the app and the
accuracy study alike.

Stretch of a constraint is |L/L0 − 1|. Torn constraints (state.alive == 0, tearing.py) are left out
of every measure: they hold no energy and their length is a gap, not a stretch. Energy is kinetic +
gravitational (height from y = 0) + elastic, the elastic part from the solver's own force estimate:

    springs  ½ k (L − L0)² per spring (the force the integrator uses)
    xpbd     ½ α f² per constraint with f = λ/h², λ the multiplier of the last substep
             (Macklin et al. 2016): at convergence f = −C/α and this equals C²/(2α), but an
             unconverged solve leaves a residual C the constraint never pushed against, and
             C²/(2α) would count it as stored energy (with α = 1e-8 m/N, kilojoules)
    pbd      none: rigid constraints store no energy

The solve's error (`solve_error`) is how far a frame ends from the equilibrium the solver
aims at, per constraint |C + α̃λ| / L0 (C = L0 − L, α̃ = α/h² per constraint, λ the last
substep's multiplier), the max over the intact constraints: for xpbd the residual of the
implicit step of the material's own elastic energy, so a fabric that stretches under load
as its compliance says has error 0; for pbd (α = 0, λ unused) it is |C|/L0, the stretch,
since the rigid constraint's equilibrium is its rest length. The adaptive substep control
bounds this, not the stretch.

Numerical damping (`free_energy`, and the runner's bookkeeping) is energy lost that no key
asked for, as a share of the energy the sheet could still give up: the total above the
lowest it could reach (`potential_floor`), per second.
Kernels here keep IEEE semantics (no fastmath) because a NaN must show as NaN.
"""

from __future__ import annotations

import math
from typing import TYPE_CHECKING

import numpy as np

from ..jit import kernel
from ..model import ClothModel
from ..state import ClothState

if TYPE_CHECKING:
    from ...scene import Scene


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
    of every frame (NumPy's isfinite(...).all() would allocate two per-particle masks in
    every frame)."""
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
def max_solve_error(x, edges, rest, alive, lambdas, alpha_tilde) -> float:
    """max |C + α̃λ| / L0 over the intact constraints (C = L0 − L; α̃ per constraint); NaN if
    any length is NaN. One pass, no temporaries: the controller's measure after every frame."""
    worst = 0.0
    for e in range(edges.shape[0]):
        if not alive[e]:
            continue
        # λ is accumulated with C = L0 − L in the projection (xpbd/constraints.py): the signs
        r = abs(rest[e] - edge_length(x, edges, e) - alpha_tilde[e] * lambdas[e]) / rest[e]
        if r != r:
            return r
        if r > worst:
            worst = r
    return worst


def per_constraint(values, count: int) -> np.ndarray:
    """A scalar or per-constraint α̃ (or λ) as a contiguous (count,) float64 array (an array
    already so is returned as it is)."""
    arr = np.asarray(values, dtype=np.float64)
    if arr.ndim == 0:
        return np.full(count, float(arr))
    if arr.shape != (count,):
        raise ValueError(f"expected one value per constraint ({count}), got {arr.shape}")
    return np.ascontiguousarray(arr)


def solve_error(model: ClothModel, x: np.ndarray, alive: np.ndarray,
                lambdas: np.ndarray | None, alpha_tilde) -> float:
    """max |C + α̃λ| / L0 (module docstring): `lambdas` the last substep's multipliers (None:
    none kept, as pbd), `alpha_tilde` α/h² per constraint or one for all (0 for pbd). Pass
    per-constraint arrays to allocate nothing."""
    m = model.num_constraints
    if not m:
        return 0.0
    lam = np.zeros(m) if lambdas is None else per_constraint(lambdas, m)
    return float(max_solve_error(x, model.edges, model.rest_length, alive, lam,
                                 per_constraint(alpha_tilde, m)))


@kernel(fastmath=False)
def _kinetic(mass, v) -> float:
    total = 0.0
    for i in range(v.shape[0]):
        total += mass[i] * (v[i, 0] * v[i, 0] + v[i, 1] * v[i, 1] + v[i, 2] * v[i, 2])
    return 0.5 * total


@kernel(fastmath=False)
def _weighted_height(mass, x) -> float:
    total = 0.0
    for i in range(x.shape[0]):
        total += mass[i] * x[i, 1]
    return total


@kernel(fastmath=False)
def _xpbd_elastic(lambdas, alpha_tilde, h2) -> float:
    """Σ ½ α f² with f = λ/h² and α = α̃h²: Σ ½ α̃ λ²/h²."""
    total = 0.0
    for e in range(lambdas.shape[0]):
        total += alpha_tilde[e] * lambdas[e] * lambdas[e]
    return 0.5 * total / h2


@kernel(fastmath=False)
def _lowest_heights(mass, anchors, nearest, distance, floor, skin) -> float:
    """Σ m_i · (the lowest y particle i can reach): its nearest pin's anchor less its flat
    distance to it, and no lower than the floor's skin (when `floor`)."""
    total = 0.0
    for i in range(mass.shape[0]):
        y = anchors[nearest[i], 1] - distance[i]
        if floor and y < skin:
            y = skin
        total += mass[i] * y
    return total


def grid_spread(model: ClothModel, x: np.ndarray) -> float:
    """The largest distance between neighbours along the grid's rows and columns, over their
    rest spacing: how far the sheet has spread, whichever constraints it has (a fabric
    without structural edges has none between them)."""
    return _grid_spread(x, model.nx, model.nz, model.spacing_x, model.spacing_z)


@kernel(fastmath=False)
def _grid_spread(x, nx, nz, dx, dz):
    """Squared distances over squared spacings, the root taken once: the guard asks every
    frame."""
    worst = 0.0
    for row in range(nz):
        for col in range(nx):
            i = row * nx + col
            if col + 1 < nx:
                d = ((x[i, 0] - x[i + 1, 0]) ** 2 + (x[i, 1] - x[i + 1, 1]) ** 2
                     + (x[i, 2] - x[i + 1, 2]) ** 2) / (dx * dx)
                if d > worst or d != d:  # a NaN is kept
                    worst = d
            if row + 1 < nz:
                j = i + nx
                d = ((x[i, 0] - x[j, 0]) ** 2 + (x[i, 1] - x[j, 1]) ** 2
                     + (x[i, 2] - x[j, 2]) ** 2) / (dz * dz)
                if d > worst or d != d:
                    worst = d
    return math.sqrt(worst)


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
    return float(_kinetic(model.mass, state.v))


def gravitational_energy(model: ClothModel, state: ClothState, scene: Scene) -> float:
    """Σ m g y (height from y = 0), J; 0 without gravity."""
    if not scene.forces.gravity:
        return 0.0
    return scene.forces.gravity_strength * float(_weighted_height(model.mass, state.x))


def xpbd_elastic_energy(lambdas: np.ndarray, alpha_tilde: np.ndarray, h: float) -> float:
    """Σ ½ α f² (f = λ/h²) over constraints of multipliers `lambdas` and α̃ = α/h²
    `alpha_tilde` (one per constraint) at a substep of h, J; 0 before any substep."""
    if h <= 0.0 or not len(lambdas):
        return 0.0
    return float(_xpbd_elastic(lambdas, alpha_tilde, h * h))


def energy(model: ClothModel, state: ClothState, scene: Scene, solver=None) -> float:
    """Kinetic + gravitational + elastic energy, J, the elastic part by `solver`'s own
    estimate (solvers.base.SolverBase.elastic_energy; none without a solver)."""
    elastic = 0.0 if solver is None else solver.elastic_energy(state)
    return kinetic_energy(model, state) + gravitational_energy(model, state, scene) + elastic


def potential_floor(model: ClothModel, state: ClothState, scene: Scene,
                    pin_distance: np.ndarray | None, nearest_pin: np.ndarray | None
                    ) -> float | None:
    """A lower bound of the gravitational energy the sheet could reach (J): each particle no
    lower than its nearest pin's anchor minus its flat-sheet distance to that pin (the sheet
    does not stretch), nor than the floor's skin. None when nothing bounds it (no pins, no
    floor: the sheet may fall for ever), and 0 without gravity."""
    if not scene.forces.gravity:
        return 0.0
    s = scene.scene
    skin = s.floor_height + s.thickness
    g = scene.forces.gravity_strength
    if pin_distance is not None and len(state.anchors):
        return g * float(_lowest_heights(model.mass, state.anchors, nearest_pin, pin_distance,
                                         s.floor, skin))
    if s.floor:
        return g * skin * float(model.mass.sum())
    return None


def free_energy(total: float, floor: float, model: ClothModel) -> float:
    """The energy the sheet could still give up, J: its total above `floor`
    (potential_floor). Never below a millionth of the sheet's weight times its size, so a
    sheet at rest divides by something."""
    tiny = 1e-6 * max(float(model.mass.sum()) * 9.81 * model.extent, 1e-12)
    return max(total - floor, tiny)
