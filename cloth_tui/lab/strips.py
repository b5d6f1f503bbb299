"""The lab's specimens: rectangular sheets of the scene format, held by pin groups (the
clamps and hooks), and a timed run of the simulator on them."""

from __future__ import annotations

import contextlib
import time
from typing import Callable


class SpecimenBuilt(Exception):
    """Raised by warmed_simulation within `specimen_only()`: the measure got as far as a
    scene that validated, where the simulation would start."""


_specimen_only = False


@contextlib.contextmanager
def specimen_only():
    """Within the `with`, a test's measure stops (SpecimenBuilt) once its specimen's scene
    is built and validated, before any simulation: a cheap check that a resolution can run,
    made before a study spends minutes on the resolutions below it."""
    global _specimen_only
    _specimen_only = True
    try:
        yield
    finally:
        _specimen_only = False


def specimen_problem(experiment, n: int, material, solver) -> str | None:
    """Why the test's specimen at resolution `n` cannot be built for `material` (its scene
    refused), or None: every case is built up to where its simulation would start, nothing
    run."""
    from ..scene import SceneError
    from .study import LabError

    for case in experiment.cases(material):
        try:
            with specimen_only():
                experiment.measure(case, n, material, solver)
        except SpecimenBuilt:
            continue
        except (SceneError, LabError) as e:
            return str(e)
    return None


def particles_across(width: float, length: float, segments: int) -> int:
    """Particles across a strip of `width` whose `length` has `segments` links: the count
    whose spacing is nearest the links' (at least 2: a sheet needs two rows)."""
    return max(2, round(width / length * segments) + 1)


def strip_scene(*, size: list[float], resolution: list[int], pins: list[dict],
                behavior: dict, material=None, material_section: dict | None = None):
    """A validated Scene: the sheet `size` = [width (x), length (z)] m at `resolution` =
    [nx, nz] particles, nothing pinned but `pins`, no floor, gravity 9.81 m/s². A
    `material_section` is the scene's [material] (the fabric simulated); else a `material`
    gives the sheet only its mass, areal density × area."""
    from ..scene import from_dict

    cloth_keys = {"size": list(size), "resolution": list(resolution), "pinned": "none",
                  "mass_model": "area"}
    sections = {}
    if material_section is not None:
        sections["material"] = material_section
    elif material is not None:
        cloth_keys["mass"] = material.areal_density * size[0] * size[1]
    return from_dict({"cloth": cloth_keys,
                      "forces": {"gravity": True, "gravity_strength": 9.81, "wind": False},
                      "scene": {"floor": False, "object": "none"},
                      "behavior": {"adaptive": False} | behavior,
                      "pins": pins} | sections, "lab")


def warmed_simulation(scene):
    """A Simulation of `scene` whose kernels have run once (compiling or loading them is
    not the test's wall time), started again from t = 0."""
    from ..sim.run.runner import Simulation

    if _specimen_only:
        raise SpecimenBuilt
    sim = Simulation(scene)
    sim.advance_frame()
    sim.reset()
    return sim


def timed_frames(sim, frames: int, each: Callable | None = None) -> float:
    """Runs `frames` frames, calling `each(sim)` after every one; returns the wall time of
    the frames alone (s)."""
    wall = 0.0
    for _ in range(frames):
        t0 = time.perf_counter()
        sim.advance_frame()
        wall += time.perf_counter() - t0
        if each is not None:
            each(sim)
    return wall
