"""The position-based solvers, PBD and XPBD: the stages they supply to a substep, whose
order pipeline.py holds: the forces and the prediction integrate_verlet (x_prev ← x;
x ← x + (1−D)·v·h + a·h²), the constraint projection (`iterations` coloured Gauss-Seidel
passes, xpbd.py; PBD is XPBD with compliance 0) and update_velocities (v ← (x − x_prev)/h,
clamped to max_speed). All kernels are compiled with nogil so the simulation thread
leaves the GIL to the UI.
"""

from __future__ import annotations

import math

import numpy as np

from .fabric_solve import ProjectFabric
from .hierarchical_pbd import ProjectHierarchy
from .jit import kernel
from .material import damping_factor as decay_factor
from .params import StepParams
from .protocols import Effect, ForceEffect
from .stages import damping_factor
from .xpbd import ProjectConstraints


@kernel()
def integrate_verlet(x, x_prev, v, accel, inv_mass, h, keep, max_speed):
    """Position Verlet with damping. The step's displacement, velocity and acceleration terms
    together, is clamped to max_speed·h: no particle outruns the colliders' thickness or
    the constraints, whatever force or impulse acts on it."""
    h2 = h * h
    max_step = max_speed * h
    for i in range(x.shape[0]):
        if inv_mass[i] == 0.0:
            x_prev[i, 0] = x[i, 0]
            x_prev[i, 1] = x[i, 1]
            x_prev[i, 2] = x[i, 2]
        else:
            dx = v[i, 0] * keep * h + accel[i, 0] * h2
            dy = v[i, 1] * keep * h + accel[i, 1] * h2
            dz = v[i, 2] * keep * h + accel[i, 2] * h2
            d2 = dx * dx + dy * dy + dz * dz
            if d2 > max_step * max_step:
                s = max_step / math.sqrt(d2)
                dx *= s
                dy *= s
                dz *= s
            x_prev[i, 0] = x[i, 0]
            x_prev[i, 1] = x[i, 1]
            x_prev[i, 2] = x[i, 2]
            x[i, 0] += dx
            x[i, 1] += dy
            x[i, 2] += dz
        accel[i, 0] = 0.0
        accel[i, 1] = 0.0
        accel[i, 2] = 0.0


@kernel()
def update_velocities(x, x_prev, v, inv_mass, inv_h, max_speed):
    """v ← (x − x_prev)/h, a free particle's clamped to max_speed as the springs' are: a
    contact or constraint correction at a short substep would otherwise read as a speed the
    next prediction clamps anyway (a 5 cm push at h = 2 µs is 25 km/s). Pins keep the speed
    they are driven at. A NaN fails the comparison and stays visible."""
    vmax2 = max_speed * max_speed
    for i in range(x.shape[0]):
        v[i, 0] = (x[i, 0] - x_prev[i, 0]) * inv_h
        v[i, 1] = (x[i, 1] - x_prev[i, 1]) * inv_h
        v[i, 2] = (x[i, 2] - x_prev[i, 2]) * inv_h
        s2 = v[i, 0] * v[i, 0] + v[i, 1] * v[i, 1] + v[i, 2] * v[i, 2]
        if inv_mass[i] != 0.0 and s2 > vmax2:
            s = max_speed / math.sqrt(s2)
            v[i, 0] *= s
            v[i, 1] *= s
            v[i, 2] *= s


class IntegrateVerlet:
    name = "integrate_verlet"

    def __init__(self, model, params: StepParams):
        self.inv_mass = model.inv_mass
        self.params = params

    def keep(self, h: float) -> float:
        """Velocity kept over a substep of h: behavior.damping's share per 18 ms, or the
        material's decay rate."""
        p = self.params
        if p.material is not None:
            return decay_factor(p.material.damping, h)
        return damping_factor(p.damping, h)

    def apply(self, state, h):
        integrate_verlet(state.x, state.x_prev, state.v, state.accel, self.inv_mass, h,
                         self.keep(h), self.params.max_speed)


class UpdateVelocities:
    name = "update_velocities"

    def __init__(self, model, params: StepParams):
        self.inv_mass = model.inv_mass
        self.params = params

    def apply(self, state, h):
        update_velocities(state.x, state.x_prev, state.v, self.inv_mass, 1.0 / h,
                          self.params.max_speed)


class PositionBasedSolver:
    """PBD (compliance 0: rigid constraints, stiffer with more iterations), hierarchical
    PBD (hpbd: PBD's constraints, with coarse levels projected before them) or XPBD
    (compliance α > 0: a material of stiffness 1/α). The force effects run as stages before
    the verlet prediction, adding to state.accel. With a material (model.fabric; xpbd, or
    hpbd, which then corrects the edges' λ between the passes: fabric_hierarchy.py) the
    constraints are the fabric's, each with its own α (fabric_solve.ProjectFabric), and
    the damping is its decay rate, exp(−damping·h) per substep. Damping and the speed limit
    are read from `params` each substep; the projection's numbers (iterations, α̃, which its
    sweeps keep per slot) are given to it again by `retune` when the params change."""

    def __init__(self, model, behavior, forces: list[ForceEffect], h: float,
                 params: StepParams):
        b = behavior
        self.name = b.solver
        self._xpbd = b.solver == "xpbd"
        self._h = h
        fabric = model.fabric
        self._hierarchy: ProjectHierarchy | None = None
        self._integrate: list[Effect] = list(forces)
        self._integrate.append(IntegrateVerlet(model, params))
        if fabric is not None:
            if b.solver in ("hpbd", "xpbd"):
                self.projection = ProjectFabric(model, params.iterations, h,
                                                hierarchy=b.solver == "hpbd")
            else:
                raise ValueError("a material's constraints are xpbd's or hpbd's "
                                 "(scene.validate says so)")
            self._constraints: list[Effect] = [self.projection]
        else:
            self.projection = ProjectConstraints(
                model, params.iterations, params.compliance if self._xpbd else 0.0, h,
                name="project_xpbd_constraints" if self._xpbd else "project_constraints")
            self._constraints = [self.projection] if model.num_constraints else []
            if b.solver == "hpbd" and model.num_constraints:
                # the coarse levels first, then the fine passes (hierarchical_pbd.py)
                self._hierarchy = ProjectHierarchy(model)
                self._constraints.insert(0, self._hierarchy)
        self._velocities = UpdateVelocities(model, params)

    def retune(self, params: StepParams, model) -> None:
        """Take the projection's numbers from `params` and `model` (its masses and its
        fabric's α, model.refitted), between frames."""
        projection = self.projection
        projection.iterations = params.iterations
        if isinstance(projection, ProjectFabric):
            projection.retune(model.fabric, self._h)
            return
        if self._xpbd:
            projection.set_compliance(params.compliance, self._h)
        projection.refresh_masses()
        if self._hierarchy is not None:
            self._hierarchy.refresh_masses()

    @property
    def passes_per_substep(self) -> float:
        """The constraint work of a substep in fine passes: the iterations, and for hpbd
        its coarse levels' projections as a share of the sheet's constraints."""
        passes = float(self.projection.iterations)
        if self._hierarchy is not None:
            passes += self._hierarchy.projections / max(1, self._hierarchy.model.num_constraints)
        return passes

    @property
    def lambdas(self) -> np.ndarray:
        """Multipliers λ of the last substep, N·s², one per constraint (model.edges order);
        all zero for PBD, whose rigid constraints store no elastic energy."""
        return self.projection.lambdas

    @property
    def alpha_tilde(self):
        """α/h² of the constraints (model.edges order): a float for every one alike, or an
        array of one per constraint (a material's)."""
        return self.projection.alpha_tilde

    def integrate(self) -> list[Effect]:
        return self._integrate

    def constraints(self) -> list[Effect]:
        return self._constraints

    def velocities(self) -> Effect:
        return self._velocities
