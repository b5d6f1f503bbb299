"""The scene's checks that involve more than one key (or a key and a derived quantity: the
grid a size and resolution make), run once a scene's keys are each valid."""

from __future__ import annotations

import math
from typing import TYPE_CHECKING, Any

from . import object_shapes, solver_specs
from .materials.section import solver_problem
from .pin_groups import check_groups, grid_of, lowest_offset
from .scene_keys import SceneError

if TYPE_CHECKING:
    from .scene import Cloth, Scene

NAIVE_MAX_PARTICLES = 128 * 128  # naive self-collision is O(N²): beyond this, the hash


def validate(scene: Scene) -> None:
    """Checks that involve more than one key."""
    b = scene.behavior
    problem = solver_problem(scene.material, b.solver)
    if problem:
        raise SceneError(problem)
    runs = solver_specs.spec(b.solver).integrators
    if b.integrator not in ("auto",) + runs:
        able = " or ".join(f'"{n}"' for n in solver_specs.names()
                           if b.integrator in solver_specs.spec(n).integrators)
        raise SceneError(f"behavior.integrator = {b.integrator!r} needs behavior.solver = "
                         f"{able}; {b.solver} runs {', '.join(runs)}")
    if b.wave and 2 * math.pi * b.wave_amplitude * b.wave_frequency > b.max_speed:
        raise SceneError(f"behavior.wave_amplitude = {b.wave_amplitude:g} m at "
                         f"behavior.wave_frequency = {b.wave_frequency:g} Hz drives the edge at "
                         f"{2 * math.pi * b.wave_amplitude * b.wave_frequency:.3g} m/s; "
                         f"2π·amplitude·frequency must not exceed behavior.max_speed = "
                         f"{b.max_speed:g} m/s")
    for i, o in enumerate(scene.objects):
        object_shapes.check_object(o, f"objects[{i}]")
    c, s = scene.cloth, scene.scene
    check_groups(scene.pins, *grid_of(c))
    holds_particles = (c.pinned not in ("none", "random") or (c.pinned == "random" and
                                                              c.pin_fraction > 0) or b.wave
                       or any(g.stiffness == 1.0 for g in scene.pins))
    # the wave's trough, or the lowest a pin group holds its particles
    lowest_held = c.height + min(-b.wave_amplitude if b.wave else 0.0,
                                 lowest_offset(scene.pins))
    if s.floor and holds_particles and lowest_held < s.floor_height + s.thickness:
        # Held particles cannot be pushed out of the floor: the contact could never hold.
        raise SceneError(f"held particles (cloth.pinned = \"{c.pinned}\""
                         f"{', behavior.wave' if b.wave else ''}"
                         f"{', [[pins]]' if scene.pins else ''}) reach down to "
                         f"{lowest_held:g} m, inside the floor (scene.floor_height = "
                         f"{s.floor_height:g} m + scene.thickness = {s.thickness:g} m); raise "
                         "cloth.height or lower the floor")
    nx, nz = _check_grid(scene.cloth)
    if b.self_collision == "naive" and nx * nz > NAIVE_MAX_PARTICLES:
        raise SceneError(f"behavior.self_collision = \"naive\" is O(N²) and limited to "
                         f"{NAIVE_MAX_PARTICLES} particles (128 × 128; cloth.resolution "
                         f"gives {nx} × {nz}); use \"hash\"")


def _check_grid(cloth: Cloth) -> tuple[int, int]:
    """The sheet's (nx, nz), refused when a side would have a single particle (a sheet of one
    row has no cells). Neither side can exceed MAX_RESOLUTION: a pair's entries are checked
    against it, and an integer resolution gives the shorter side no more than the longer."""
    nx, nz = cloth.grid_shape()
    for axis, count, line in (("x", nx, "column"), ("z", nz, "row")):
        if count < 2:
            width, length = cloth.dimensions()
            raise SceneError(f"cloth.size = {_toml_text(cloth.size)} at cloth.resolution = "
                             f"{_toml_text(cloth.resolution)} makes a sheet of a single {line} "
                             f"(1 particle along {axis}: {width:g} m × {length:g} m with "
                             f"{max(nx, nz)} along the longer side); raise cloth.resolution or "
                             "give [nx, nz] with at least 2 along each side")
    return nx, nz


def _toml_text(value: Any) -> str:
    """A number or a list of numbers as written in a scene file."""
    if isinstance(value, list):
        return "[" + ", ".join(f"{v:g}" for v in value) + "]"
    return f"{value:g}"
