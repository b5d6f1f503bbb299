"""What the scene accepts can be simulated, and what it refuses is refused with one clean
line: integers of hundreds of digits, deep nesting, tiny and subnormal values, tiny
directions, control characters in keys and file names (issue 19)."""

import dataclasses
import math
import warnings

import numpy as np
import pytest
from hypothesis import HealthCheck, given, settings
from hypothesis import strategies as st

from cloth_tui import scene as sc
from cloth_tui import scene_files as sf
from cloth_tui.safe_text import escape_controls

FLOAT_KEYS = [k for k in sc.all_keys() if sc.key_spec(k).type in ("float", float)]
VEC_KEYS = [k for k in sc.all_keys() if sc.key_spec(k).metadata["kind"].startswith("vec3")]
OBJECT_VEC_KEYS = [f.name for f in dataclasses.fields(sc.SceneObject)
                   if f.metadata["kind"].startswith("vec3")]
DIRECTION_KEYS = [k for k in VEC_KEYS if "nonzero" in sc.key_spec(k).metadata["kind"]]


def refused(fn) -> str:
    with pytest.raises(sc.SceneError) as e:
        fn()
    msg = str(e.value)
    assert msg and "\n" not in msg and "\x1b" not in msg
    return msg


def toml_doc(dotted: str, raw: str) -> str:
    section, name = dotted.split(".")
    return f"[{section}]\n{name} = {raw}\n"


# Integers of hundreds (to thousands, past Python's 4300-digit conversion limit) of digits.
huge_integers = st.builds(lambda sign, n, d: sign + d + "0" * n, st.sampled_from(["", "-"]),
                          st.integers(300, 6000), st.sampled_from("123456789"))


@settings(max_examples=60, suppress_health_check=[HealthCheck.too_slow])
@given(st.sampled_from(FLOAT_KEYS), huge_integers)
def test_huge_integers_for_float_keys_are_refused(dotted, digits):
    refused(lambda: sf.loads(toml_doc(dotted, digits)))
    refused(lambda: sf.apply_overrides(sc.Scene(), [f"{dotted}={digits}"]))
    if len(digits) < 4000:
        refused(lambda: sc.Scene().with_value(dotted, int(digits)))


@settings(max_examples=60, suppress_health_check=[HealthCheck.too_slow])
@given(st.sampled_from(VEC_KEYS), st.integers(0, 2), huge_integers)
def test_huge_integers_as_vector_elements_are_refused(dotted, index, digits):
    vec = ["0.5", "0.5", "0.5"]
    vec[index] = digits
    raw = "[" + ", ".join(vec) + "]"
    refused(lambda: sf.loads(toml_doc(dotted, raw)))
    refused(lambda: sf.apply_overrides(sc.Scene(), [f"{dotted}={raw}"]))


@settings(max_examples=20, suppress_health_check=[HealthCheck.too_slow])
@given(st.integers(1000, 20000), st.sampled_from([("[", "]"), ("{a = ", "}")]),
       st.sampled_from(["cloth.mass", "forces.wind_direction", "appearance.cloth_texture"]))
def test_deep_nesting_is_refused_in_one_line(depth, brackets, dotted):
    opening, closing = brackets
    raw = opening * depth + "1" + closing * depth
    assert "nested too deeply" in refused(lambda: sf.loads(toml_doc(dotted, raw)))
    assert "nested too deeply" in refused(
        lambda: sf.apply_overrides(sc.Scene(), [f"{dotted}={raw}"]))


def nested_list(depth: int):
    value: list = []
    for _ in range(depth):
        value = [value]
    return value


@settings(max_examples=10)
@given(st.integers(2000, 50000), st.sampled_from(FLOAT_KEYS + VEC_KEYS))
def test_deeply_nested_python_values_are_refused(depth, dotted):
    refused(lambda: sc.Scene().with_value(dotted, nested_list(depth)))


# Directions shorter than the minimum: tiny, subnormal and zero components.
tiny = st.one_of(st.just(0.0), st.floats(min_value=-sc.MIN_DIRECTION_NORM / 2,
                                         max_value=sc.MIN_DIRECTION_NORM / 2),
                 st.sampled_from([5e-324, -5e-324, 1e-200, 2.2e-308]))


@settings(max_examples=100)
@given(st.sampled_from(DIRECTION_KEYS + ["objects.normal"]), st.tuples(tiny, tiny, tiny))
def test_directions_too_short_to_normalise_are_refused(dotted, vec):
    vec = list(vec)
    if math.hypot(*vec) >= sc.MIN_DIRECTION_NORM:
        return
    if dotted == "objects.normal":
        doc = {"objects": [{"type": "plane", "normal": vec}]}
    else:
        section, name = dotted.split(".")
        doc = {section: {name: vec}}
    refused(lambda: sc.from_dict(doc))


@settings(max_examples=100)
@given(st.sampled_from(DIRECTION_KEYS), st.lists(
    st.floats(min_value=-1e6, max_value=1e6, allow_subnormal=True), min_size=3, max_size=3))
def test_accepted_directions_normalise_finitely(dotted, vec):
    try:
        scene = sc.Scene().with_value(dotted, vec)
    except sc.SceneError:
        assert math.hypot(*vec) < sc.MIN_DIRECTION_NORM
        return
    d = np.asarray(scene.get(dotted))
    with np.errstate(over="raise", divide="raise", invalid="raise"):  # a tiny part may underflow
        unit = d / np.sqrt(d @ d)  # the way the kernels normalise: through the squared norm
    assert np.isfinite(unit).all() and abs(np.linalg.norm(unit) - 1) < 1e-9


@settings(max_examples=60)
@given(st.sampled_from(FLOAT_KEYS), st.floats(min_value=5e-324, max_value=1e-3))
def test_tiny_values_below_a_key_minimum_are_refused(dotted, value):
    spec = sc.key_spec(dotted).metadata
    if spec["lo"] is None or value > spec["lo"] or (value == spec["lo"] and not spec["lo_open"]):
        return
    refused(lambda: sc.Scene().with_value(dotted, value))
    refused(lambda: sf.apply_overrides(sc.Scene(), [f"{dotted}={value!r}"]))


# Keys whose tiny positive values used to be accepted and then could not be simulated.
SIMULABLE_LOWS = {"cloth.mass": st.floats(min_value=5e-324, max_value=1e-3),
                  "behavior.frame_rate": st.floats(min_value=5e-324, max_value=2.0)}


@settings(max_examples=25, deadline=None, suppress_health_check=[HealthCheck.too_slow])
@given(st.sampled_from(sorted(SIMULABLE_LOWS)).flatmap(
    lambda k: st.tuples(st.just(k), SIMULABLE_LOWS[k])), st.booleans())
def test_accepted_tiny_values_simulate(key_value, wind):
    """Validate what can be simulated, not only what is non-zero: an accepted value runs a
    few frames with finite positions and no floating-point warnings."""
    from cloth_tui.sim.run.runner import Simulation

    dotted, value = key_value
    try:
        scene = sc.Scene().with_values({dotted: value, "cloth.resolution": 5,
                                        "forces.wind": wind})
    except sc.SceneError:
        return
    with warnings.catch_warnings():
        warnings.simplefilter("error", RuntimeWarning)
        sim = Simulation(scene)
        for _ in range(3):
            sim.advance_frame()
    assert np.isfinite(sim.state.x).all()
    assert sim.stats().finite


def test_the_reported_examples():
    refused(lambda: sf.apply_overrides(sc.Scene(), ["cloth.mass=5e-324"]))
    refused(lambda: sf.apply_overrides(sc.Scene(), ["behavior.frame_rate=1e-12"]))
    refused(lambda: sf.apply_overrides(sc.Scene(), ["forces.wind_direction=[0,1e-200,0]"]))
    refused(lambda: sc.from_dict({"objects": [{"type": "capsule", "normal": [0, 1e-200, 0]}]}))
    refused(lambda: sf.loads("[cloth]\nmass = " + "1" * 400))


# -- control characters in keys, values and file names --------------------------------------

hostile_text = st.lists(st.one_of(st.characters(codec="utf-8"),
                                  st.sampled_from(["\x1b]0;x\x07", "\x1b[31m", "\n", "\r",
                                                   "\x9b", "\u202e"])),
                        min_size=1, max_size=12).map("".join)


def toml_key(text: str) -> str:
    return '"' + "".join(f"\\U{ord(c):08x}" for c in text) + '"'


@settings(max_examples=100)
@given(hostile_text, st.sampled_from(["section", "key", "value"]))
def test_scene_errors_escape_control_characters(text, where):
    doc = {"section": f"[{toml_key(text)}]\na = 1\n",
           "key": f"[cloth]\n{toml_key(text)} = 1\n",
           "value": f"[cloth]\npinned = {toml_key(text)}\n"}[where]
    try:
        sf.loads(doc)
    except sc.SceneError as e:
        assert str(e) == escape_controls(str(e))
        return
    assert where == "value" and text in sc.PIN_MODES


@settings(max_examples=40, deadline=None)
@given(st.text(st.one_of(st.characters(codec="utf-8", exclude_characters="/\x00"),
                         st.sampled_from(["\n", "\x1b", "\r", "\t"])), min_size=1, max_size=12))
def test_a_scene_file_name_with_control_characters_saves_and_loads(tmp_path_factory, name):
    folder = tmp_path_factory.mktemp("names")
    scene = sc.Scene(name=name).with_value("cloth.mass", 0.3)
    try:
        path = sf.save(scene, folder / f"{name}.toml")
    except sc.SceneError:  # a name the file system refuses (too long in bytes)
        assert len(f"{name}.toml".encode()) > 255
        return
    loaded = sf.load(path)
    assert loaded == scene and loaded.name == name
    assert sf.load(sf.save(loaded, folder / "again.toml")) == scene


# -- combinations that cannot start legally ------------------------------------------------

@settings(max_examples=30, deadline=None, suppress_health_check=[HealthCheck.too_slow])
@given(st.floats(-5, 2), st.floats(-2, 1), st.floats(0, 0.2),
       st.sampled_from(["corners", "one_edge", "four_edges", "random", "none"]), st.booleans(),
       st.floats(0, 1))
def test_held_particles_never_start_inside_the_floor(height, floor, thickness, pinned, wave,
                                                     amplitude):
    """A scene is refused, or its contacts hold from the first frame: pinned (or wave-held)
    particles below the floor can never be pushed out."""
    from cloth_tui.sim.run.runner import Simulation

    try:
        scene = sc.Scene().with_values({
            "cloth.height": height, "scene.floor_height": floor, "scene.thickness": thickness,
            "cloth.pinned": pinned, "cloth.pin_fraction": 0.3, "cloth.resolution": 6,
            "behavior.wave": wave, "behavior.wave_amplitude": amplitude,
            "behavior.max_speed": 1e3})
    except sc.SceneError as e:
        assert "\n" not in str(e)
        return
    sim = Simulation(scene)
    for _ in range(4):
        sim.advance_frame()
    assert sim.stats().penetration <= thickness + 0.01
