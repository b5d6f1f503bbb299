"""The solver registry: a solver is one folder and one registry line, and everything that
offers solvers (the scene's choices, material validation, the lab, the bench, the key
reference) offers a new one without being told its name. A toy damped Jacobi solver is
registered here at run time and run through a scene."""

import numpy as np
import pytest

from cloth_tui.scene import Scene, SceneError
from cloth_tui.sim import solvers
from cloth_tui.sim.run.runner import Simulation
from cloth_tui.sim.solvers.base import SolverBase, SolverSpec
from cloth_tui.sim.solvers.xpbd.verlet import IntegrateVerlet, UpdateVelocities

TOY = "toy_jacobi"


class ProjectJacobi:
    """Every constraint's PBD correction computed from the same positions, then each
    particle moved by the mean of its corrections (damped Jacobi, ω = 1 over the count)."""
    name = "project_jacobi"

    def __init__(self, model, iterations: int):
        self.model = model
        self.iterations = iterations

    def apply(self, state, h):
        m = self.model
        a, b = m.edges[:, 0], m.edges[:, 1]
        w = m.inv_mass
        count = np.bincount(np.concatenate([a, b]), minlength=m.num_particles)
        count = np.maximum(count, 1)[:, None]
        for _ in range(self.iterations):
            d = state.x[b] - state.x[a]
            length = np.linalg.norm(d, axis=1)
            ok = (length > 0) & (w[a] + w[b] > 0) & state.alive.astype(bool)
            s = np.zeros_like(length)
            s[ok] = (length[ok] - m.rest_length[ok]) / (length[ok] * (w[a] + w[b])[ok])
            corr = np.zeros_like(state.x)
            np.add.at(corr, a, (w[a] * s)[:, None] * d)
            np.add.at(corr, b, -(w[b] * s)[:, None] * d)
            state.x += corr / count


class ToyJacobi(SolverBase):
    name = TOY

    def __init__(self, model, behavior, forces, h, params):
        super().__init__(model, behavior, forces, h, params)
        self._integrate = list(forces) + [IntegrateVerlet(model, params)]
        self._project = ProjectJacobi(model, params.iterations)
        self._velocities = UpdateVelocities(model, params)

    def integrate(self):
        return self._integrate

    def constraints(self):
        return [self._project]

    def velocities(self):
        return self._velocities

    @property
    def passes_per_substep(self) -> float:
        return float(self._project.iterations)


@pytest.fixture
def toy():
    solvers.register(SolverSpec(name=TOY, summary="a toy Jacobi", load=lambda: ToyJacobi))
    yield
    solvers.unregister(TOY)


def test_a_registered_solver_is_offered_everywhere(toy):
    from cloth_tui.bench.accuracy import CONSTRAINT_SOLVERS
    from cloth_tui.bench.accuracy_cost import solver_runs
    from cloth_tui.lab.study import MATERIAL_SOLVERS
    from cloth_tui.scene import SOLVERS
    from cloth_tui.scene_reference import reference_markdown

    assert TOY in SOLVERS and TOY in solvers.names()
    assert TOY in CONSTRAINT_SOLVERS  # the work-precision study runs it
    assert (TOY, {"behavior.solver": TOY}) in solver_runs()  # so does the cost bench
    assert TOY not in MATERIAL_SOLVERS  # its spec takes no material
    assert f"one of {', '.join(SOLVERS)}" in reference_markdown()  # the key reference
    with pytest.raises(SceneError, match="needs behavior.solver"):
        Scene().with_values({"behavior.solver": TOY, "material.preset": "denim"})


def test_a_registered_solver_runs_a_scene(toy):
    scene = Scene().with_values({"behavior.solver": TOY, "cloth.resolution": 10,
                                 "cloth.pinned": "one_edge", "scene.floor": False,
                                 "behavior.tethers": False, "behavior.adaptive": False,
                                 "behavior.substeps": 8, "behavior.iterations": 20})
    sim = Simulation(scene)
    for _ in range(60):
        sim.advance_frame()
    s = sim.stats()
    assert s.solver == TOY and "project_jacobi" in s.effects
    assert s.finite and not s.halted
    # held by one edge, it has swung down its length, held together by the toy's
    # projection alone (no tethers: without it the sheet would fall apart)
    assert s.min_y < scene.cloth.height - 0.8
    assert s.max_stretch < 0.2


def test_unknown_and_duplicate_names_are_refused(toy):
    with pytest.raises(ValueError, match="registered already"):
        solvers.register(SolverSpec(name=TOY, summary="again", load=lambda: ToyJacobi))
    with pytest.raises(SceneError, match="behavior.solver"):
        Scene().with_values({"behavior.solver": "no_such_solver"})
