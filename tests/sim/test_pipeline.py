"""The step builder: one stage order for every solver, solvers supplying their own stages."""

import numpy as np
import pytest

from cloth_tui.scene import Scene, SceneError
from cloth_tui.sim import pipeline, solvers
from cloth_tui.sim.model import build_model
from cloth_tui.sim.state import ClothState


def build(**keys):
    s = Scene().with_value("cloth.resolution", 8).with_value("scene.object", "sphere")
    for k, v in keys.items():
        s = s.with_value(k.replace("__", "."), v)
    material = None if s.material is None else s.material.material
    model = build_model(s.cloth, s.behavior, s.pins, material)
    return pipeline.build(s, model), ClothState.from_model(model), model


CONTACTS_AFTER = ["contact_friction", "contacts_after_friction"]
# Each registered solver's own stages (integrate, constraints, velocities), without and with
# a material; None: the solver refuses a material (scene validation says so).
STAGES = {
    "pbd": ((["gravity", "integrate_verlet"], ["project_constraints"], "update_velocities"),
            None),
    "hpbd": ((["gravity", "integrate_verlet"], ["project_coarse_levels", "project_constraints"],
              "update_velocities"),
             (["gravity", "integrate_verlet"], ["project_fabric_levels"], "update_velocities")),
    "xpbd": ((["gravity", "integrate_verlet"], ["project_xpbd_constraints"],
              "update_velocities"),
             (["gravity", "integrate_verlet"], ["project_fabric_constraints"],
              "update_velocities")),
    # springs: integrator "auto" is implicit Euler; no constraint stage, no tethers
    "springs": ((["integrate_implicit_euler"], [], "correct_velocities"), None),
    # lbfgs: xpbd's prediction, then the implicit step solved as a minimisation; no tethers
    "lbfgs": ((["gravity", "integrate_verlet"], ["solve_implicit_step"], "update_velocities"),
              (["gravity", "integrate_verlet"], ["solve_implicit_step"], "update_velocities")),
}


def test_the_stage_table_covers_every_registered_solver():
    assert set(STAGES) == set(solvers.names())


@pytest.mark.parametrize("material", [None, "denim"])
@pytest.mark.parametrize("solver", sorted(STAGES))
def test_every_solver_runs_the_one_stage_order(solver, material):
    keys = {"behavior__solver": solver, "behavior__tethers": True}
    if material:
        keys["material__preset"] = material
    expected = STAGES[solver][1 if material else 0]
    if expected is None:
        with pytest.raises(SceneError, match="needs behavior.solver"):
            build(**keys)
        return
    integrate, constraints, velocities = expected
    step, _, model = build(**keys)
    assert step.solver.name == solver
    tethers = ["enforce_tethers"] if solvers.spec(solver).tethers and not material else []
    assert (model.tether_pin is not None) == bool(tethers)
    contacts = ["collide_floor", "collide_sphere"] + tethers
    resolve = ["resolve_contacts"] if constraints else []
    assert step.names == (integrate + contacts + constraints + resolve + CONTACTS_AFTER
                          + ["apply_pins", velocities])


def test_xpbd_multipliers_are_public_and_converge_to_minus_c_over_alpha():
    alpha = 1e-4
    step, state, model = build(behavior__solver="xpbd", behavior__compliance=alpha,
                               behavior__iterations=1000, scene__object="none")
    for _ in range(30):
        step.substep(state)
    lam = step.solver.lambdas
    assert lam.shape == (model.num_constraints,)
    d = np.linalg.norm(state.x[model.edges[:, 1]] - state.x[model.edges[:, 0]], axis=1)
    c = d - model.rest_length  # after the substep's projection (pins and velocities move no
    #                            free particle's position)
    alpha_t = alpha / step.h ** 2
    free = (model.inv_mass[model.edges[:, 0]] + model.inv_mass[model.edges[:, 1]]) > 0
    assert np.abs(lam).max() > 0.0
    # Gauss-Seidel's fixed point C + α̃λ = 0, to what the passes left unconverged
    assert np.abs(lam[free] + c[free] / alpha_t).max() < 0.01 * np.abs(lam).max()


@pytest.mark.parametrize("solver", ["pbd", "xpbd"])
def test_a_crushed_sheet_unfolds_with_both_position_based_solvers(solver):
    # All particles at one point: the constraints have no direction of their own. PBD picked
    # one from the indices; XPBD skipped them and the sheet stayed a point. One kernel now.
    step, state, model = build(behavior__solver=solver, cloth__pinned="none",
                               scene__object="none", scene__floor=False)
    state.x[:] = state.x.mean(axis=0)
    state.x_prev[:] = state.x
    for _ in range(10):
        step.substep(state)
    assert np.ptp(state.x, axis=0).max() > 0.1 * model.extent
