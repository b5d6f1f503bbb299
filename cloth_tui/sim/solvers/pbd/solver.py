"""PBD: XPBD with α = 0 (Ten Minute Physics' reading): rigid constraints, stiffer the more
passes a substep makes, which store no elastic energy."""

from __future__ import annotations

from ...params import StepParams
from ..xpbd.solver import XPBDSolver


class PBDSolver(XPBDSolver):
    name = "pbd"
    projection_name = "project_constraints"

    def compliance(self, params: StepParams) -> float:
        return 0.0

    def halt_advice(self) -> str:
        return "raise behavior.substeps, or weaken the forces (gravity, wind, custom fields)"
