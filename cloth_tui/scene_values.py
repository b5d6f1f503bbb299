"""One scene key's value checked against its declaration (scene_keys.key: its type, range,
choices, kind), and the words an error uses for what the key allows."""

from __future__ import annotations

import dataclasses
import math
import re
from typing import Any

from .png_header import MAX_TEXTURE_PIXELS
from .scene_keys import MIN_DIRECTION_NORM, SceneError
from .texture_names import BUILTIN_TEXTURES
from .user_values import finite_float, short_repr, texture_file_problem


def describe_allowed(f: dataclasses.Field) -> str:
    m = f.metadata
    if m["choices"]:
        return "one of " + ", ".join(m["choices"])
    if m["kind"] == "color":
        return "a colour #rrggbb"
    if m["kind"] == "texture":
        side = math.isqrt(MAX_TEXTURE_PIXELS)
        return (f"none, {', '.join(BUILTIN_TEXTURES)} or a .png path of at most "
                f"{MAX_TEXTURE_PIXELS} pixels ({side}×{side})")
    if m["kind"].startswith("vec3"):
        return ("[x, y, z] of numbers within ±1e+06" +
                (f", of length ≥ {MIN_DIRECTION_NORM:g}" if "nonzero" in m["kind"] else ""))
    t = value_type(f)
    lo = "" if m["lo"] is None else f"{m['lo']:g} {'<' if m['lo_open'] else '≤'} "
    hi = "" if m["hi"] is None else f" {'<' if m['hi_open'] else '≤'} {m['hi']:g}"
    kind = {"bool": "true or false", "int": "an integer", "float": "a number",
            "str": "a string"}.get(t, t)
    one = f"{kind}{' with ' + lo + 'value' + hi if (lo or hi) else ''}"
    if m["pair"]:
        return f"{one}, or [{', '.join(m['pair'])}], two of them"
    return one


def value_type(f: dataclasses.Field) -> str:
    """The declared type's name ("int", "float", ...); for a key that also takes a pair
    (`float | list`), the type of one number."""
    t = f.type if isinstance(f.type, str) else f.type.__name__
    return t.split("|")[0].strip()


def coerce(section_obj: Any, name: str, value: Any, dotted: str) -> Any:
    """Check one value against its declaration; return it in its canonical Python type."""
    f = {f.name: f for f in dataclasses.fields(section_obj)}[name]
    m, t = f.metadata, value_type(f)

    def bad(reason: str = "") -> SceneError:
        shown = short_repr(value)
        return SceneError(f"{dotted} = {shown} is not allowed{': ' + reason if reason else ''}; "
                          f"expected {describe_allowed(f)}")

    if m["kind"].startswith("vec3"):
        if not isinstance(value, (list, tuple)) or len(value) != 3:
            raise bad()
        out = []
        for v in value:
            if isinstance(v, bool) or not isinstance(v, (int, float)):
                raise bad()
            v = finite_float(v)
            if v is None:
                raise bad("not a finite number")
            out.append(v)
        if any(abs(v) > 1e6 for v in out):
            raise bad("too large")
        if "nonzero" in m["kind"] and not math.hypot(*out) >= MIN_DIRECTION_NORM:
            raise bad("zero-length direction" if not any(out) else "too short to give a direction")
        return out
    if t == "bool":
        if not isinstance(value, bool):
            raise bad()
        return value
    if t == "str":
        if not isinstance(value, str):
            raise bad()
        if m["choices"] and value not in m["choices"]:
            raise bad()
        if m["kind"] == "color" and not re.fullmatch(r"#[0-9a-fA-F]{6}", value):
            raise bad()
        if m["kind"] == "texture":
            _check_texture(value, bad)
        return value
    if t in ("int", "float"):
        if m["pair"] and isinstance(value, (list, tuple)):
            if len(value) != 2:
                raise bad(f"a list needs two entries, {' and '.join(m['pair'])}")
            return [_number(v, t, m, bad) for v in value]
        return _number(value, t, m, bad)
    raise bad()


def _number(value: Any, t: str, m: Any, bad) -> int | float:
    """One int or float value checked against its declaration's range."""
    if isinstance(value, bool) or not isinstance(value, (int, float)):
        raise bad()
    if t == "int":
        if isinstance(value, float):
            if not (math.isfinite(value) and value.is_integer()):
                raise bad()
            value = int(value)
    else:
        as_float = finite_float(value)
        if as_float is None:
            raise bad("not a finite number")
        value = as_float
    lo, hi = m["lo"], m["hi"]
    if lo is not None and (value < lo or (m["lo_open"] and value == lo)):
        raise bad()
    if hi is not None and (value > hi or (m["hi_open"] and value == hi)):
        raise bad()
    return value


def _check_texture(value: str, bad) -> None:
    if value == "none" or value in BUILTIN_TEXTURES:
        return
    if not value.lower().endswith(".png"):
        raise bad()
    problem = texture_file_problem(value)
    if problem:
        raise bad(problem)
