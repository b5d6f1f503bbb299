"""The scene schema: typed dataclasses and dict conversion (files and `--set` overrides:
scene_files; one value's checks: scene_values; checks across keys: scene_checks; the
README's key reference: scene_reference).

Every key is declared once, with its default, unit, allowed range and help text, in the
field metadata below. Validation, the README's key reference and the TUI's panels all read
that one declaration, so they cannot drift apart.
"""

from __future__ import annotations

import copy
import dataclasses
import math
from dataclasses import dataclass, field
from typing import Any

from . import object_shapes as shapes
from . import solver_specs as solver_registry
from .materials.errors import MaterialError
from .materials.section import (MaterialSection, is_material_key, section_from_value,
                                section_to_table, with_material_key)
from .pin_groups import PinGroup, group_to_dict, groups_from_list
from .png_header import MAX_TEXTURE_SIDE
from .scene_checks import validate
from .scene_keys import SECTIONS, SceneError, key, vec3
from .scene_values import coerce
from .texture_names import BUILTIN_TEXTURES

# (the schema as one module: callers read these here too)
from .scene_keys import MIN_DIRECTION_NORM as MIN_DIRECTION_NORM  # noqa: E402
from .scene_values import describe_allowed as describe_allowed  # noqa: E402
from .scene_values import value_type as value_type  # noqa: E402

MAX_RESOLUTION = 512  # particles along either side of the sheet
TEXTURE_DOC = (f"none, a built-in texture name ({', '.join(BUILTIN_TEXTURES)}) or a PNG path; "
               f"sides above {MAX_TEXTURE_SIDE} px are downscaled")
MASS_MODELS = ("area", "uniform")
PIN_MODES = ("none", "corners", "one_edge", "two_edges", "four_edges", "random")
SOLVERS = solver_registry.Names()  # live: a solver registered later is a choice too
INTEGRATORS = ("auto", "verlet", "explicit_euler", "symplectic_euler", "midpoint", "rk4",
               "implicit_euler", "bdf2")
SHAPE_TYPES = shapes.single_object_names()  # scene.object: the original's shapes
OBJECT_TYPES = shapes.names()
CUSTOM_FIELDS = ("none", "black_hole", "anti_gravity", "vortex", "tractor_beam")


@dataclass
class Cloth:
    size: float | list = key(1.0, "the sheet: a number is the side of a square, [width, "
                             "length] a rectangle (width along x, length along z)", unit="m",
                             lo=0.01, hi=100.0, pair=("width", "length"))
    resolution: int | list = key(26, "particles along the longer side, the other side getting "
                                 "the count nearest to equal spacing (the original's 500 → "
                                 "26); or [nx, nz], particles along x and along z", lo=2,
                                 hi=MAX_RESOLUTION, pair=("nx", "nz"))
    pinned: str = key("corners", "which particles are held fixed", choices=PIN_MODES)
    pin_fraction: float = key(0.05, "share of particles pinned when pinned = \"random\"",
                              lo=0.0, hi=1.0)
    # lo: even at resolution 512 a particle keeps ≥ 4e-12 kg, so 1/mass stays far from overflow
    mass: float = key(0.2, "mass of the whole sheet", unit="kg", lo=1e-6, hi=1e6)
    mass_model: str = key("area", "how the mass is shared: area (each particle its share of "
                          "the sheet: edges ½, corners ¼ of an interior one) or uniform (the "
                          "original's equal masses)", choices=MASS_MODELS)
    height: float = key(0.25, "initial height of the flat, horizontal sheet", unit="m",
                        lo=-1e3, hi=1e3)

    def dimensions(self) -> tuple[float, float]:
        """(width, length) in metres: the sheet's extent along x and along z."""
        if isinstance(self.size, list):
            return float(self.size[0]), float(self.size[1])
        return float(self.size), float(self.size)

    def extent(self) -> float:
        """The sheet's longer side (m): what views, fog and the ground scale with."""
        return max(self.dimensions())

    def grid_shape(self) -> tuple[int, int]:
        """(nx, nz): particles along x (columns) and along z (rows)."""
        if isinstance(self.resolution, list):
            return int(self.resolution[0]), int(self.resolution[1])
        width, length = self.dimensions()
        n = int(self.resolution)
        if width == length:
            return n, n
        longer, shorter = max(width, length), min(width, length)
        other = _nearest_spacing_count(shorter, longer / (n - 1))
        return (n, other) if width >= length else (other, n)


def _nearest_spacing_count(side: float, spacing: float) -> int:
    """The particle count along `side` whose spacing is nearest to `spacing`: 1 when the side
    is under half a spacing (a single row, which validate refuses)."""
    if side / spacing < 0.5:
        return 1
    below = max(2, math.floor(side / spacing) + 1)
    return min((below, below + 1), key=lambda c: (abs(side / (c - 1) - spacing), -c))


@dataclass
class Forces:
    integrate: bool = key(True, "advance the simulation (off freezes the sheet, as in the "
                                "original)")
    gravity: bool = key(True, "apply gravity")
    gravity_strength: float = key(9.81, "gravitational acceleration, downward (−y)", unit="m/s²",
                                  lo=0.0, hi=1e4)
    wind: bool = key(False, "apply aerodynamic wind force")
    wind_strength: float = key(5.0, "air speed", unit="m/s", lo=0.0, hi=500.0)
    wind_direction: list = vec3([0.0, 0.0, 1.0], "direction the air moves (normalised)",
                                nonzero=True)
    wind_mode: str = key("constant", "constant air speed, or gusty (sinusoidal in time)",
                         choices=("constant", "gusty"))
    custom: str = key("none", "custom force field", choices=CUSTOM_FIELDS)
    custom_strength: float = key(10.0, "strength of the custom field", unit="m/s²",
                                 lo=0.0, hi=1e5)
    custom_rate: float = key(0.5, "how fast the custom field varies in time", unit="Hz",
                             lo=0.0, hi=1e3)
    rain: bool = key(False, "rain drops strike random particles")
    rain_strength: float = key(0.01, "downward displacement of the struck particle", unit="m",
                               lo=0.0, hi=10.0)
    rain_rate: float = key(20.0, "drops per second", unit="1/s", lo=0.0, hi=1e5)


# [[objects]]: the keys every object has, then each shape's own (object_shapes.py)
SceneObject = dataclasses.make_dataclass("SceneObject", [
    ("type", "str", key("sphere", "shape of the object", choices=OBJECT_TYPES)),
    ("center", "list", vec3([0.0, -0.25, 0.0], "centre (a point on the plane, for planes)",
                            unit="m")),
    *shapes.object_keys(),
    ("friction", "float", key(-1.0, "Coulomb friction μ 0–1 (−1: use scene.friction)",
                              lo=-1.0, hi=1.0)),
    ("motion", "str", key("static", "static, or orbit (the original's slow circle)",
                          choices=("static", "orbit"))),
])
SceneObject.__module__ = __name__  # for pickling and its repr's sake, as if declared here


@dataclass
class SceneSection:
    floor: bool = key(True, "collide with the floor")
    floor_height: float = key(-0.5, "height of the floor", unit="m", lo=-1e3, hi=1e3)
    object: str = key("none", "the original's single object", choices=("none",) + SHAPE_TYPES)
    friction: float = key(0.9, "Coulomb friction μ of objects and floor (static; kinetic 0.8 μ)",
                          lo=0.0, hi=1.0)
    moving: bool = key(False, "the object follows the original's slow orbit")
    thickness: float = key(0.005, "collision skin kept between cloth and objects", unit="m",
                           lo=0.0, hi=1.0)


@dataclass
class Behavior:
    structural: bool = key(True, "structural constraints (1-away in row and column)")
    shear: bool = key(True, "shear constraints (1-away diagonally)")
    bending: bool = key(True, "bending constraints (2-away in row and column)")
    iterations: int = key(4, "constraint passes per substep", lo=1, hi=1000)
    substeps: int = key(4, "substeps per frame (with adaptive: the fewest it uses)", lo=1,
                        hi=1000)
    adaptive: bool = key(True, "raise the substeps when a frame's solve error exceeds "
                         "error_tolerance (or its numerical damping energy_tolerance), lower "
                         "them again when there is slack")
    error_tolerance: float = key(0.05, "largest solve error a frame may leave on any "
                                 "constraint, |C + α̃λ| as a share of its rest length: how far "
                                 "from the material's own equilibrium (pbd: the stretch; 0.05: "
                                 "5 %)", lo=0.001, hi=10.0)
    energy_tolerance: float = key(0.0, "largest numerical damping a frame may show: share of "
                                  "the sheet's free energy lost per second that no damping key "
                                  "asked for (0.05: 5 %/s, about 10 % over 2 s); 0: unbounded "
                                  "(lbfgs still bounds energy made, at 0.25/s)",
                                  unit="1/s", lo=0.0, hi=100.0)
    max_substeps: int = key(128, "adaptive: the most substeps per frame it may use",
                            lo=1, hi=1000)
    # lo: a frame of at most 1 s; the app waits one frame period of wall time per frame
    frame_rate: float = key(60.0, "frames per simulated second", unit="1/s", lo=1.0,
                            hi=10000.0)
    damping: float = key(0.03, "share of velocity lost per 18 ms (the original's step)",
                         lo=0.0, hi=1.0, hi_open=True)
    solver: str = key(solver_registry.DEFAULT,
                      ", ".join(solver_registry.spec(n).summary for n in sorted(
                          SOLVERS, key=lambda n: n != solver_registry.DEFAULT)),
                      choices=SOLVERS)
    integrator: str = key("auto", "time integrator; auto: each solver's own ("
                          + solver_registry.auto_integrators()
                          + "; lbfgs: bdf2 where energy_tolerance is set); a solver refuses one "
                          "it does not run", choices=INTEGRATORS)
    compliance: float = key(1e-8, "xpbd compliance (inverse stiffness)", unit="m/N", lo=0.0,
                            hi=1.0)
    stiffness: float = key(2000.0, "springs: spring constant (explicit integrators need "
                           "h < 0.66·√(m/k) per substep, see Accuracy)", unit="N/m", lo=0.0,
                           lo_open=True, hi=1e9)
    spring_damping: float = key(0.5, "springs: damping along each spring", unit="N·s/m",
                                lo=0.0, hi=1e6)
    tethers: bool = key(True, "long-range attachments (pbd, hpbd, xpbd; where pins exist): no "
                        "particle may drift farther from its nearest pin than on the flat "
                        "sheet, which keeps large sheets from over-stretching")
    tear: bool = key(False, "constraints stretched beyond tear_stretch (with a material's "
                     "tear_strength: loaded beyond it) break and leave the solve (tethers "
                     "are then off: a torn sheet has no fixed geodesics)")
    tear_stretch: float = key(0.3, "stretch L/L0 − 1 at which a constraint breaks, in "
                              "tension only (0.3: 30 %)", lo=0.0, lo_open=True, hi=100.0)
    self_collision: str = key("off", "keep the sheet from passing through itself",
                              choices=("off", "naive", "hash"))
    max_speed: float = key(50.0, "particle speed limit (guards against tunnelling)",
                           unit="m/s", lo=0.0, lo_open=True, hi=1e5)
    wave: bool = key(False, "drive one edge up and down, hold the opposite edge")
    wave_amplitude: float = key(0.1, "wave amplitude", unit="m", lo=0.0, hi=100.0)
    wave_frequency: float = key(1.0, "wave frequency", unit="Hz", lo=0.0, hi=100.0)
    seed: int = key(0, "seed of every random choice (random pins, rain)", lo=0, hi=2**63 - 1)


@dataclass
class Appearance:
    wireframe: bool = key(False, "draw the cloth as a wireframe")
    auto_rotate: bool = key(False, "orbit the camera")
    show_constraints: bool = key(False, "draw constraints coloured by family")
    show_pins: bool = key(True, "mark the held particles with small dots in the app's "
                          "preview (renders from the command line leave them out)")
    cloth_color: str = key("#aa2929", "cloth colour", kind="color")
    cloth_specular: str = key("#030303", "cloth reflection (specular colour)", kind="color")
    ground_color: str = key("#404761", "ground colour", kind="color")
    ground_emissive: str = key("#000000", "ground emission colour", kind="color")
    fog_color: str = key("#cce0ff", "background / fog colour", kind="color")
    cloth_texture: str = key("none", TEXTURE_DOC, kind="texture")
    ground_texture: str = key("none", TEXTURE_DOC, kind="texture")


@dataclass
class Scene:
    cloth: Cloth = field(default_factory=Cloth)
    forces: Forces = field(default_factory=Forces)
    scene: SceneSection = field(default_factory=SceneSection)
    behavior: Behavior = field(default_factory=Behavior)
    appearance: Appearance = field(default_factory=Appearance)
    objects: list[SceneObject] = field(default_factory=list)
    pins: list[PinGroup] = field(default_factory=list)  # [[pins]]: pin_groups.py
    material: MaterialSection | None = None  # [material]: materials/section.py
    name: str = field(default="default", compare=False)

    def copy(self) -> "Scene":
        return copy.deepcopy(self)

    def get(self, dotted: str) -> Any:
        section, name = split_key(dotted)
        return getattr(getattr(self, section), name)

    def with_value(self, dotted: str, value: Any) -> "Scene":
        """A validated copy with one key changed; raises SceneError and leaves self untouched."""
        return self.with_values({dotted: value})

    def with_values(self, values: dict[str, Any]) -> "Scene":
        """A copy with several keys changed, each checked, then the whole validated once (so
        keys that constrain each other may change in any order)."""
        new = self.copy()
        for dotted, value in values.items():
            if dotted == "pins":  # the whole [[pins]] array (pin_groups.py)
                new.pins = groups_from_list(value)
                continue
            if is_material_key(dotted):
                new.material = _material(with_material_key, new.material, dotted, value)
                continue
            section, name = split_key(dotted)
            sec = getattr(new, section)
            setattr(sec, name, coerce(sec, name, value, renamed(dotted)))
        validate(new)
        return new

    def with_objects(self, objects: list[dict[str, Any]]) -> "Scene":
        """A validated copy whose [[objects]] are `objects` (tables as in a scene file); the
        other sections, valid already, are copied rather than read again (the old objects
        are not copied at all: they are replaced)."""
        new = dataclasses.replace(self, objects=[]).copy()
        new.objects = _objects_from_list(objects)
        validate(new)
        return new

    def placed_objects(self) -> list[tuple[str, SceneObject]]:
        """(key, SceneObject) of every object of the scene: scene.object (in the original's
        placement), then [[objects]] in order."""
        out = []
        if self.scene.object != "none":
            shape = shapes.SHAPES[self.scene.object]
            out.append(("scene.object", SceneObject(type=shape.name, motion="orbit"
                                                    if self.scene.moving else "static",
                                                    **shape.single_object)))
        out += [(f"objects[{k}]", o) for k, o in enumerate(self.objects)]
        return out

    def with_pins(self, pins: list[dict[str, Any]]) -> "Scene":
        """A validated copy whose [[pins]] are `pins` (tables as in a scene file)."""
        return from_dict({**to_dict(self), "pins": pins}, self.name)


SECTION_TYPES = {"cloth": Cloth, "forces": Forces, "scene": SceneSection,
                 "behavior": Behavior, "appearance": Appearance}


def key_spec(dotted: str) -> dataclasses.Field:
    section, name = split_key(dotted)
    return {f.name: f for f in dataclasses.fields(SECTION_TYPES[section])}[name]


def all_keys() -> list[str]:
    return [f"{s}.{f.name}" for s in SECTIONS for f in dataclasses.fields(SECTION_TYPES[s])]


# Keys renamed, old name → new, still accepted in files and overrides. The tolerance bounds
# the solve's error, which for pbd is the stretch the old name bounded.
RENAMED_KEYS = {"behavior.stretch_tolerance": "behavior.error_tolerance"}


def renamed(dotted: str) -> str:
    """How an error names a key: a renamed one by both names."""
    new = RENAMED_KEYS.get(dotted)
    return f"{dotted} (now {new})" if new else dotted


def split_key(dotted: str) -> tuple[str, str]:
    parts = RENAMED_KEYS.get(dotted, dotted).split(".")
    if len(parts) != 2 or parts[0] not in SECTION_TYPES:
        raise SceneError(f"unknown key {dotted!r}: expected SECTION.KEY with SECTION one of "
                         f"{', '.join(SECTIONS)}")
    names = [f.name for f in dataclasses.fields(SECTION_TYPES[parts[0]])]
    if parts[1] not in names:
        raise SceneError(f"unknown key {dotted!r}: [{parts[0]}] has {', '.join(names)}")
    return parts[0], parts[1]


integrator_for = solver_registry.integrator_for  # (its home is the solvers' registry)


def _section_from_dict(cls: type, data: Any, where: str) -> Any:
    if not isinstance(data, dict):
        raise SceneError(f"[{where}] must be a table, got {type(data).__name__}")
    obj = cls()
    names = [f.name for f in dataclasses.fields(cls)]
    for k, v in data.items():
        shown = renamed(f"{where}.{k}")
        k = RENAMED_KEYS.get(f"{where}.{k}", f"{where}.{k}")[len(where) + 1:]
        if k not in names:
            raise SceneError(f"unknown key {where}.{k}: [{where}] has {', '.join(names)}")
        setattr(obj, k, coerce(obj, k, v, shown))
    return obj


def _objects_from_list(v: Any) -> list[SceneObject]:
    if not isinstance(v, list):
        raise SceneError("objects must be an array of tables ([[objects]])")
    if len(v) > 64:
        raise SceneError(f"objects: {len(v)} objects; at most 64 are allowed")
    return [_section_from_dict(SceneObject, o, f"objects[{i}]") for i, o in enumerate(v)]


def from_dict(data: dict, name: str = "scene") -> Scene:
    if not isinstance(data, dict):
        raise SceneError("a scene must be a table of sections")
    scene = Scene(name=name)
    for k, v in data.items():
        if k in SECTION_TYPES:
            setattr(scene, k, _section_from_dict(SECTION_TYPES[k], v, k))
        elif k == "objects":
            scene.objects = _objects_from_list(v)
        elif k == "pins":
            scene.pins = groups_from_list(v)
        elif k == "material":
            scene.material = _material(section_from_value, v)
        else:
            raise SceneError(f"unknown section [{k}]: allowed are {', '.join(SECTIONS)}, "
                             "[[objects]], [[pins]], [material]")
    validate(scene)
    return scene


def to_dict(scene: Scene, only_changed: bool = False) -> dict:
    default = Scene()
    out: dict[str, Any] = {}
    for s in SECTIONS:
        sec, dsec = getattr(scene, s), getattr(default, s)
        d = {f.name: getattr(sec, f.name) for f in dataclasses.fields(sec)
             if not only_changed or getattr(sec, f.name) != getattr(dsec, f.name)}
        if d:
            out[s] = d
    if scene.objects:
        out["objects"] = [dataclasses.asdict(o) for o in scene.objects]
    if scene.pins:
        out["pins"] = [group_to_dict(g) for g in scene.pins]
    if scene.material is not None:
        out["material"] = section_to_table(scene.material)
    return out


def _material(fn, *args) -> MaterialSection | None:
    """A materials/section.py call, its MaterialError as a SceneError."""
    try:
        return fn(*args)
    except MaterialError as e:
        raise SceneError(str(e)) from None
