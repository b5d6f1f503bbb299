"""Property tests: whatever document or override arrives, the loader gives a valid scene or
one clear SceneError, never another exception."""

import math

from hypothesis import HealthCheck, given, settings
from hypothesis import strategies as st

from cloth_tui import scene as sc
from cloth_tui import scene_files as sf



def nested(depth: int) -> list:
    value: list = []
    for _ in range(depth):
        value = [value]
    return value


values = st.one_of(
    st.none(), st.booleans(), st.integers(min_value=-2**70, max_value=2**70),
    st.floats(allow_nan=True, allow_infinity=True), st.text(max_size=20),
    st.lists(st.floats(allow_nan=True, allow_infinity=True), max_size=4),
    st.lists(st.integers(-3, 3), min_size=3, max_size=3),
    st.sampled_from(["none", "corners", "hash", "sphere", "#ff0000", "maze", "rk4", "springs"]),
    # the corners issue 19 found: integers of hundreds of digits, deep nesting, tiny non-zero
    # vectors and subnormals, control characters
    st.builds(lambda k, sign: sign * 10 ** k, st.integers(300, 5000), st.sampled_from([1, -1])),
    st.builds(lambda depth: nested(depth), st.integers(500, 3000)),
    st.lists(st.sampled_from([0.0, 5e-324, -5e-324, 1e-200, 1e-7, 2.2e-308]), min_size=3,
             max_size=3),
    st.floats(min_value=0, max_value=1e-300),
    st.text(st.sampled_from("\x1b\n\r\x07\x9b\u202e[];=a"), max_size=12),
)
keys = st.sampled_from(sc.all_keys() + ["cloth.bogus", "nope.size", "objects", "cloth"])


def check(fn):
    try:
        result = fn()
    except sc.SceneError as e:
        msg = str(e)
        assert msg and msg.isprintable()  # one line, no control characters
        return None
    assert isinstance(result, sc.Scene)
    sc.validate(result)
    for k in sc.all_keys():
        v = result.get(k)
        if isinstance(v, float):
            assert math.isfinite(v)
    return result


@settings(max_examples=300, suppress_health_check=[HealthCheck.too_slow])
@given(st.dictionaries(keys, values, max_size=6))
def test_random_documents_load_or_fail_clearly(doc):
    nested: dict = {}
    for dotted, v in doc.items():
        if "." in dotted:
            s, k = dotted.split(".", 1)
            if isinstance(nested.get(s, {}), dict):
                nested.setdefault(s, {})[k] = v
        else:
            nested[dotted] = v
    check(lambda: sc.from_dict(nested))


@settings(max_examples=300)
@given(keys, values)
def test_random_values_through_with_value(key, value):
    check(lambda: sc.Scene().with_value(key, value))


@settings(max_examples=300)
@given(st.text(max_size=60))
def test_random_override_text(text):
    check(lambda: sf.apply_overrides(sc.Scene(), [text]))


@settings(max_examples=200)
@given(st.binary(max_size=200))
def test_binary_garbage_as_toml(data):
    def load():
        return sf.loads(data.decode("utf-8", errors="replace"))
    check(load)


@settings(max_examples=100)
@given(st.lists(st.dictionaries(st.sampled_from(["type", "center", "radius", "size", "normal",
                                                  "axis", "length", "friction", "motion",
                                                  "bogus"]), values,
                                 max_size=4), max_size=3))
def test_random_objects(objects):
    check(lambda: sc.from_dict({"objects": objects}))
