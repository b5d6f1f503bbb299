"""External forces, as accelerations added to `state.accel` before integration.

Every force offers two entry points:
    apply(state, h)                      adds to state.accel at the state's own time
    accumulate(x, v, t, out_accel)       adds the acceleration at any positions/velocities,
                                         for solvers (springs + RK4) that evaluate forces at
                                         intermediate states
`apply` only calls `accumulate`, so both always agree. Pinned particles (inverse mass 0)
receive no acceleration. Formulas, units and defaults are in docs/physics.md.

The wave is not a force but a kinematic drive of pinned anchors; it lives here because it
runs where forces run (before integration, every substep).
"""

from __future__ import annotations

import math

import numpy as np

from ..jit import kernel
from ..params import StepParams

AIR_DENSITY = 1.2            # kg/m³, air at sea level and 20 °C
DRAG_COEFFICIENT = 1.2       # flat plate facing the flow (pressure drag; Hoerner ≈ 1.17–1.28)
GUST_PERIOD = 2.5            # s, period of the gusty wind's speed oscillation
GUST_DEPTH = 0.5             # gusty speed = strength·(1 + depth·sin(2πt/period))
FIELD_CENTER = (0.0, 0.0, 0.0)  # m, centre/axis point of the custom fields (the sheet's
#                                 rest centre is 0.25 m above it, as in the original)
SOFTENING = 0.1              # m, black hole / vortex softening length ε (no singular centre)
REFERENCE_RADIUS = 0.5       # m, black hole: distance at which |a| ≈ custom_strength
BEAM_RADIUS = 0.3            # m, tractor beam: Gaussian radius of the beam
BEAM_ORBIT = 0.25            # m, tractor beam: its axis circles the field centre at this radius
DEGENERATE_AREA = 1e-14      # m², twice a triangle's area below which it has no normal


# -- kernels --------------------------------------------------------------------------------
@kernel()
def add_uniform_acceleration(accel, inv_mass, ax, ay, az):
    for i in range(accel.shape[0]):
        if inv_mass[i] != 0.0:
            accel[i, 0] += ax
            accel[i, 1] += ay
            accel[i, 2] += az


@kernel()
def apply_wind(x, v, accel, inv_mass, triangles, wx, wy, wz, k):
    """Pressure drag on each triangle from the air velocity relative to it:
        F = k · A · (n·v_rel)·|n·v_rel| · n,   k = ½·ρ·C,   v_rel = w − (v0+v1+v2)/3
    n is the unit normal and A the area; F/3 goes to each corner as F/(3m). A sheet moving
    with the air (v_rel = 0) or edge-on to it (n·v_rel = 0) feels nothing."""
    for t in range(triangles.shape[0]):
        a = triangles[t, 0]
        b = triangles[t, 1]
        c = triangles[t, 2]
        e1x = x[b, 0] - x[a, 0]
        e1y = x[b, 1] - x[a, 1]
        e1z = x[b, 2] - x[a, 2]
        e2x = x[c, 0] - x[a, 0]
        e2y = x[c, 1] - x[a, 1]
        e2z = x[c, 2] - x[a, 2]
        # cross product = 2·A·n
        nx = e1y * e2z - e1z * e2y
        ny = e1z * e2x - e1x * e2z
        nz = e1x * e2y - e1y * e2x
        twice_area = math.sqrt(nx * nx + ny * ny + nz * nz)
        if twice_area < DEGENERATE_AREA:
            continue
        nx /= twice_area
        ny /= twice_area
        nz /= twice_area
        rx = wx - (v[a, 0] + v[b, 0] + v[c, 0]) / 3.0
        ry = wy - (v[a, 1] + v[b, 1] + v[c, 1]) / 3.0
        rz = wz - (v[a, 2] + v[b, 2] + v[c, 2]) / 3.0
        vn = nx * rx + ny * ry + nz * rz
        f = k * 0.5 * twice_area * vn * abs(vn) / 3.0  # newtons per corner, along n
        for p in (a, b, c):
            w = inv_mass[p] * f
            accel[p, 0] += w * nx
            accel[p, 1] += w * ny
            accel[p, 2] += w * nz


@kernel()
def apply_black_hole(x, accel, inv_mass, cx, cy, cz, s, eps2):
    """Softened attractor (Plummer): a = s·L²·(c − x)/(|c − x|² + ε²)^{3/2}.
    Far away it is s·(L/r)² toward c; at the centre it is 0, never infinite."""
    for i in range(x.shape[0]):
        if inv_mass[i] == 0.0:
            continue
        rx = cx - x[i, 0]
        ry = cy - x[i, 1]
        rz = cz - x[i, 2]
        d2 = rx * rx + ry * ry + rz * rz + eps2
        g = s / (d2 * math.sqrt(d2))
        accel[i, 0] += g * rx
        accel[i, 1] += g * ry
        accel[i, 2] += g * rz


@kernel()
def apply_vortex(x, accel, inv_mass, cx, cz, s, eps2):
    """Swirl about the vertical axis through (cx, cz), turning +x toward +z (spin along −y):
    a = s·(−dz, 0, dx)/√(dx² + dz² + ε²); magnitude s far from the axis, 0 on it."""
    for i in range(x.shape[0]):
        if inv_mass[i] == 0.0:
            continue
        dx = x[i, 0] - cx
        dz = x[i, 2] - cz
        g = s / math.sqrt(dx * dx + dz * dz + eps2)
        accel[i, 0] -= g * dz
        accel[i, 2] += g * dx


@kernel()
def apply_tractor_beam(x, accel, inv_mass, bx, bz, s, inv_r2):
    """Vertical beam through (bx, bz) lifting what it touches:
    a_y = s·exp(−d²/R²), d = horizontal distance to the beam's axis."""
    for i in range(x.shape[0]):
        if inv_mass[i] == 0.0:
            continue
        dx = x[i, 0] - bx
        dz = x[i, 2] - bz
        accel[i, 1] += s * math.exp(-(dx * dx + dz * dz) * inv_r2)


# -- effects --------------------------------------------------------------------------------
class Gravity:
    name = "gravity"
    kinematic = False

    def __init__(self, model, params: StepParams):
        self.inv_mass = model.inv_mass
        self.params = params

    def accumulate(self, x, v, t, out_accel):
        add_uniform_acceleration(out_accel, self.inv_mass, 0.0, -self.params.gravity, 0.0)

    def apply(self, state, h):
        self.accumulate(state.x, state.v, state.t, state.accel)


def wind_speed(strength: float, mode: str, t: float) -> float:
    """Air speed at time t: constant, or gusty = strength·(1 + 0.5·sin(2πt / 2.5 s))."""
    if mode == "gusty":
        return strength * (1.0 + GUST_DEPTH * math.sin(2.0 * math.pi * t / GUST_PERIOD))
    return strength


class Wind:
    name = "wind"
    kinematic = False

    def __init__(self, model, params: StepParams):
        self.params = params
        self.inv_mass, self.triangles = model.inv_mass, model.triangles
        self.k = 0.5 * AIR_DENSITY * DRAG_COEFFICIENT

    def air_velocity(self, t: float) -> np.ndarray:
        p = self.params
        return wind_speed(p.wind_speed, p.wind_mode, t) * np.asarray(p.wind_direction)

    def accumulate(self, x, v, t, out_accel):
        w = self.air_velocity(t)
        apply_wind(x, v, out_accel, self.inv_mass, self.triangles, w[0], w[1], w[2], self.k)

    def apply(self, state, h):
        self.accumulate(state.x, state.v, state.t, state.accel)


def pulse(rate: float, t: float) -> float:
    """Time variation of the black hole and the vortex: 1 + ½·sin(2π·rate·t) (1 at rate 0)."""
    return 1.0 + 0.5 * math.sin(2.0 * math.pi * rate * t)


class CustomField:
    """One of the custom fields; `strength` in m/s², `rate` in Hz (see docs/physics.md)."""
    kinematic = False

    def __init__(self, model, kind: str, params: StepParams):
        self.name = kind
        self.kind, self.params = kind, params
        self.inv_mass = model.inv_mass

    @property
    def rate(self) -> float:
        return self.params.custom_rate

    def accumulate(self, x, v, t, out_accel):
        cx, cy, cz = FIELD_CENTER
        s, k = self.params.custom_strength, self.kind
        if k == "black_hole":
            apply_black_hole(x, out_accel, self.inv_mass, cx, cy, cz,
                             s * pulse(self.rate, t) * REFERENCE_RADIUS ** 2, SOFTENING ** 2)
        elif k == "vortex":
            apply_vortex(x, out_accel, self.inv_mass, cx, cz, s * pulse(self.rate, t),
                         SOFTENING ** 2)
        elif k == "anti_gravity":
            # upward, oscillating between 0 and s: with s > g the sheet bobs up and down
            lift = 0.5 * s * (1.0 + math.sin(2.0 * math.pi * self.rate * t))
            add_uniform_acceleration(out_accel, self.inv_mass, 0.0, lift, 0.0)
        elif k == "tractor_beam":
            phase = 2.0 * math.pi * self.rate * t
            apply_tractor_beam(x, out_accel, self.inv_mass, cx + BEAM_ORBIT * math.cos(phase),
                               cz + BEAM_ORBIT * math.sin(phase), s, 1.0 / BEAM_RADIUS ** 2)

    def apply(self, state, h):
        self.accumulate(state.x, state.v, state.t, state.accel)


def wave_rows(nx: int, nz: int) -> tuple[np.ndarray, np.ndarray]:
    """(driven, held) particle indices of the wave on an nz-row, nx-column grid: the near
    edge (row nz−1, z = +length/2) is driven, the far edge (row 0, the one `one_edge` pins)
    is held."""
    idx = np.arange(nx * nz).reshape(nz, nx)
    return idx[-1, :].copy(), idx[0, :].copy()


class Wave:
    """Drives the near edge up and down: anchor y = rest y + A·sin(2π f t). The model pins
    both wave edges (build_model), so this only moves anchors; the pin pass after the
    constraints puts the particles there. Runs before integration; it targets the end of the
    substep (t + h) because that is when the pins are applied."""
    name = "wave"
    kinematic = True  # force-based solvers run `apply` once per substep, not per stage

    def __init__(self, model, amplitude: float, frequency: float):
        driven, _ = wave_rows(model.nx, model.nz)
        slot = {int(p): k for k, p in enumerate(model.pinned)}
        self.slots = np.array([slot[int(p)] for p in driven if int(p) in slot], np.int64)
        self.rest_y = model.rest_positions[model.pinned[self.slots], 1].copy()
        self.amplitude, self.frequency = amplitude, frequency

    def height(self, t: float) -> float:
        return self.amplitude * math.sin(2.0 * math.pi * self.frequency * t)

    def accumulate(self, x, v, t, out_accel):
        """Not a force: contributes no acceleration (the drive acts through the anchors)."""

    def apply(self, state, h):
        state.anchors[self.slots, 1] = self.rest_y + self.height(state.t + h)


def build_forces(scene, model, params: StepParams) -> list:
    """Force effects the scene enables, in order: gravity, wind, custom field, wave. They
    read their strengths from `params` (params.py) each time they act."""
    f, b = scene.forces, scene.behavior
    out = []
    if f.gravity and f.gravity_strength > 0:
        out.append(Gravity(model, params))
    if f.wind and f.wind_strength > 0:
        out.append(Wind(model, params))
    if f.custom != "none" and f.custom_strength > 0:
        out.append(CustomField(model, f.custom, params))
    if b.wave and len(model.pinned):
        out.append(Wave(model, b.wave_amplitude, b.wave_frequency))
    return out
