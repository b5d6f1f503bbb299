"""Contacts win over soft pins: a soft group whose target lies inside the floor or an object
leaves its particles on the surface, not dragged in (issue 40: 9.2 m into the floor at
stiffness 0.999999, 18 cm into a sphere)."""

import pytest

from cloth_tui.scene import SceneObject
from cloth_tui.scene_files import apply_overrides
from cloth_tui.sim.collision import colliders
from cloth_tui.sim.run.runner import Simulation

from ..helpers import run, scene


class ContactsLast(Simulation):
    """A run whose step has the contacts-after-soft-pins stage where pipeline.assemble is to
    put it (right after soft_pins), whether or not assemble does yet."""

    def _build_step(self):
        super()._build_step()
        names = self.step.names[len(self.step.frame_effects):]
        if ("soft_pins" in names and "contacts_after_soft_pins" not in names
                and self.step.colliders):
            self.step.effects.insert(names.index("soft_pins") + 1,
                                     colliders.ContactsAfterSoftPins(self.step.colliders))


def pulled_into(where: str, stiffness: float):
    if where == "floor":
        return apply_overrides(scene(cloth__resolution=10, cloth__pinned="none"),
                               [f"pins=[{{rows=[0,0], offset=[0,-10,0], stiffness={stiffness}}}]"])
    s = apply_overrides(scene(cloth__resolution=10, cloth__pinned="none", scene__floor=False),
                        [f"pins=[{{rows=[0,0], offset=[0,-0.4,0], stiffness={stiffness}}}]"])
    s.objects = [SceneObject(type="sphere", center=[0.0, -0.1, -0.5], radius=0.25)]
    return s


@pytest.mark.parametrize("where", ["floor", "sphere"])
@pytest.mark.parametrize("stiffness", [0.999999, 0.99])
def test_a_soft_pin_target_inside_a_collider_leaves_its_particles_outside(where, stiffness):
    st = run(ContactsLast(pulled_into(where, stiffness)), 20).stats()
    assert st.finite and st.halted is None
    assert st.penetration <= 1e-9, st.penetration


def test_the_step_runs_contacts_after_the_soft_pins():
    sim = run(Simulation(pulled_into("floor", 0.999999)), 10)
    names = sim.step.names
    assert names[names.index("soft_pins") + 1] == "contacts_after_soft_pins"
    assert sim.stats().penetration <= 1e-9
