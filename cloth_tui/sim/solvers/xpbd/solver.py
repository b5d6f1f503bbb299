"""XPBD: compliant constraints (α > 0: a material of stiffness 1/α), projected by coloured
Gauss-Seidel passes after the verlet prediction.

One substep, top to bottom (pipeline.assemble interleaves contacts and pins):
    integrate    the force effects add to state.accel; integrate_verlet predicts x
    solve        `iterations` passes over the constraints (constraints.py), or with a
                 material its edges, shear cells and bending stencils, each with its own α
                 (fabric_constraints.py)
    velocities   update_velocities: v ← (x − x_prev)/h
Damping and the speed limit are read from `params` each substep; the projection's numbers
(iterations, α̃, which its sweeps keep per slot) are given to it again by `retune`.
"""

from __future__ import annotations

import numpy as np

from ...run.measures import per_constraint, xpbd_elastic_energy
from ...params import StepParams
from ...protocols import Effect, ForceEffect
from ..base import SolverBase
from .constraints import ProjectConstraints
from .fabric_constraints import ProjectFabric, fabric_force_energy
from .verlet import IntegrateVerlet, UpdateVelocities


class XPBDSolver(SolverBase):
    name = "xpbd"
    projection_name = "project_xpbd_constraints"

    def __init__(self, model, behavior, forces: list[ForceEffect], h: float,
                 params: StepParams):
        super().__init__(model, behavior, forces, h, params)
        self._predict = IntegrateVerlet(model, params)
        self._integrate: list[Effect] = list(forces) + [self._predict]
        self.projection: ProjectConstraints | ProjectFabric
        if model.fabric is not None:
            self.projection = ProjectFabric(model, params.iterations, h,
                                            levels=self.fabric_levels(model))
            self._constraints: list[Effect] = [self.projection]
        else:
            self.projection = ProjectConstraints(model, params.iterations,
                                                 self.compliance(params), h,
                                                 name=self.projection_name)
            self._constraints = [self.projection] if model.num_constraints else []
        self._velocities = UpdateVelocities(model, params)

    def compliance(self, params: StepParams) -> float:
        """α of the original's constraints, m/N (a material's are its own)."""
        return params.compliance

    def fabric_levels(self, model):
        """A coarse correction of a material's edge multipliers between the passes, or None."""
        return None

    def retune(self, params: StepParams, model) -> None:
        """Take the prediction's fabric (its damping) and the projection's numbers from
        `params` and `model` (its masses and its fabric's α, model.refitted), between
        frames."""
        self.model = model
        self._predict.retune(model)
        projection = self.projection
        projection.iterations = params.iterations
        if isinstance(projection, ProjectFabric):
            projection.retune(model.fabric, self.h)
            return
        projection.set_compliance(self.compliance(params), self.h)
        projection.refresh_masses()

    def integrate(self) -> list[Effect]:
        return self._integrate

    def constraints(self) -> list[Effect]:
        return self._constraints

    def velocities(self) -> Effect:
        return self._velocities

    @property
    def passes_per_substep(self) -> float:
        return float(self.projection.iterations)

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

    def elastic_energy(self, state) -> float:
        """Σ ½ α f² (f = λ/h²) over the last substep's constraints; a material's shear cells
        and bending stencils included."""
        if isinstance(self.projection, ProjectFabric):
            return fabric_force_energy(self.projection, self.h)
        n = self.model.num_constraints
        if not n or (np.ndim(self.alpha_tilde) == 0 and self.alpha_tilde == 0.0):
            return 0.0  # rigid constraints (pbd) store none
        return xpbd_elastic_energy(self.lambdas, per_constraint(self.alpha_tilde, n), self.h)

    def halt_advice(self) -> str:
        return ("raise behavior.compliance or behavior.substeps, or weaken the forces "
                "(gravity, wind, custom fields)")
