"""Hierarchical PBD. Without a material: PBD's fine passes after a cascade of coarse
position levels (position_levels.py, on the grids of level_grids.py). With one: XPBD's
fabric passes with a coarse correction of the edges' multipliers after each of the first
half of the passes (multiplier_levels.py)."""

from __future__ import annotations

from ...params import StepParams
from ...protocols import ForceEffect
from ..pbd.solver import PBDSolver
from ..xpbd.fabric_constraints import ProjectFabric
from .multiplier_levels import DualHierarchy
from .position_levels import ProjectHierarchy


class HPBDSolver(PBDSolver):
    name = "hpbd"

    def __init__(self, model, behavior, forces: list[ForceEffect], h: float,
                 params: StepParams):
        super().__init__(model, behavior, forces, h, params)
        self._levels: ProjectHierarchy | None = None
        if not isinstance(self.projection, ProjectFabric) and model.num_constraints:
            # the coarse levels first, then the fine passes
            self._levels = ProjectHierarchy(model)
            self._constraints.insert(0, self._levels)

    def fabric_levels(self, model):
        return DualHierarchy(model)

    def retune(self, params: StepParams, model) -> None:
        super().retune(params, model)
        if self._levels is not None:
            self._levels.refresh_masses()

    @property
    def passes_per_substep(self) -> float:
        """The fine passes, and the coarse levels' projections as a share of the sheet's
        constraints."""
        passes = float(self.projection.iterations)
        if self._levels is not None:
            passes += self._levels.projections / max(1, self.model.num_constraints)
        return passes
