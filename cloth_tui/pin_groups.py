"""The scene's [[pins]] tables: pin groups, which hold chosen particles of the sheet.

A group chooses particles by grid index, `rows = [first, last]` and `cols = [first, last]`
(inclusive; negative counts from the end, as in Python; a range left out is all of them), or
`at = [[row, col], ...]`. It holds them `offset` (m) from their place on the flat sheet, or
along `keys = [[t, dx, dy, dz], ...]` (the offset over time, linearly interpolated and held
before the first key and after the last), exactly (`stiffness = 1`) or softly (below 1).

This module checks what needs no model (types, finiteness, ranges on the sheet's grid, keys
increasing in time); sim/pins.py resolves groups to particles and checks that a particle in
two groups is held the same way by both. Pure Python, like scene.py.
"""

from __future__ import annotations

import dataclasses
import math
from dataclasses import dataclass
from typing import Any

from .scene_keys import SceneError
from .user_values import finite_float, short_repr

MAX_PIN_GROUPS = 64
MAX_KEYS = 1000
MAX_AT = 4096  # cells listed one by one in `at`; rows/cols choose larger blocks
MAX_OFFSET = 1e3  # m, any component of an offset or key
MAX_KEY_TIME = 1e6  # s
# Stiffness s < 1 holds a group by zero-length springs totalling SOFT_PIN_SCALE·s/(1−s) N/m
# (shared evenly by its particles): 0.5 → 100 N/m, 0.9 → 900 N/m, 0.99 → 9900 N/m.
SOFT_PIN_SCALE = 100.0  # N/m


def _field(default: Any, doc: str, *, unit: str = "", lo: float | None = None,
           hi: float | None = None, kind: str = "") -> Any:
    """A pin group key, declared with the metadata scene.key uses (the panels read it)."""
    meta = dict(doc=doc, unit=unit, lo=lo, hi=hi, lo_open=False, hi_open=False,
                choices=None, kind=kind)
    if isinstance(default, list):
        return dataclasses.field(default_factory=lambda: list(default), metadata=meta)
    return dataclasses.field(default=default, metadata=meta)


@dataclass
class PinGroup:
    rows: list = _field([], "[first, last] row (along z), inclusive; negative counts from the "
                        "end; left out: every row", kind="toml")
    cols: list = _field([], "[first, last] column (along x), inclusive; negative counts from "
                        "the end; left out: every column", kind="toml")
    at: list = _field([], "[[row, col], ...]: single particles (instead of rows and cols)",
                      kind="toml")
    offset: list = _field([0.0, 0.0, 0.0], "where the group is held, relative to its place "
                          "on the flat sheet", unit="m", kind="vec3")
    stiffness: float = _field(1.0, "1 holds exactly; below 1 a soft pin: zero-length springs "
                              f"totalling {SOFT_PIN_SCALE:g}·s/(1−s) N/m over the group",
                              lo=0.0, hi=1.0)
    keys: list = _field([], "[[t, dx, dy, dz], ...]: the offset (m) over time (s), linearly "
                        "interpolated, held after the last key (instead of offset)",
                        kind="toml")

    def offset_at(self, t: float) -> tuple[float, float, float]:
        """The group's offset at time t (s)."""
        if not self.keys:
            return tuple(self.offset)
        if t <= self.keys[0][0]:
            return tuple(self.keys[0][1:])
        for (t0, *a), (t1, *b) in zip(self.keys, self.keys[1:]):
            if t <= t1:
                w = (t - t0) / (t1 - t0)
                return tuple(p + w * (q - p) for p, q in zip(a, b))
        return tuple(self.keys[-1][1:])

    def offsets(self) -> list[list[float]]:
        """Every offset the group takes: the keys' (between them it moves on straight lines)."""
        return [list(k[1:]) for k in self.keys] if self.keys else [list(self.offset)]

    def holds_the_same_as(self, other: "PinGroup") -> bool:
        return (self.offset, self.keys, self.stiffness) == (other.offset, other.keys,
                                                            other.stiffness)


PIN_KEYS = {f.name: f for f in dataclasses.fields(PinGroup)}
ALLOWED = {"rows": "[first, last], integers", "cols": "[first, last], integers",
           "at": f"[[row, col], ...], integers, at most {MAX_AT}",
           "offset": f"[dx, dy, dz], each within ±{MAX_OFFSET:g}",
           "stiffness": "a number with 0 < value ≤ 1",
           "keys": f"[[t, dx, dy, dz], ...], t increasing, 0 ≤ t ≤ {MAX_KEY_TIME:g}, at most "
                   f"{MAX_KEYS} keys"}
DEFAULT_GROUP = PinGroup()


def grid_of(cloth) -> tuple[int, int]:
    """(rows, cols) of the sheet's particle grid, from its [cloth] section."""
    nx, nz = cloth.grid_shape()
    return nz, nx


def _error(message: str) -> Exception:
    return SceneError(message)


def _number(value: Any, where: str, what: str, integer: bool = False) -> float | int:
    if isinstance(value, bool) or not isinstance(value, (int, float)):
        raise _error(f"{where} = {short_repr(value)} is not allowed; expected {what}")
    if integer:
        if isinstance(value, float) and not (math.isfinite(value) and value.is_integer()):
            raise _error(f"{where} = {short_repr(value)} is not allowed; expected {what}")
        return int(value)
    f = finite_float(value)
    if f is None:
        raise _error(f"{where}: {short_repr(value)} is not a finite number; expected {what}")
    return f


def _list(value: Any, where: str, what: str, length: int | None = None,
          most: int | None = None) -> list:
    if not isinstance(value, (list, tuple)) or (length is not None and len(value) != length):
        raise _error(f"{where} = {short_repr(value)} is not allowed; expected {what}")
    if most is not None and len(value) > most:
        raise _error(f"{where}: {len(value)} entries; at most {most} are allowed")
    return list(value)


def _offset(value: Any, where: str) -> list[float]:
    what = f"[dx, dy, dz] in m, each within ±{MAX_OFFSET:g}"
    out = [_number(v, where, what) for v in _list(value, where, what, 3)]
    if any(abs(v) > MAX_OFFSET for v in out):
        raise _error(f"{where} = {short_repr(value)} is not allowed: too large; expected {what}")
    return out


def group_from_dict(data: Any, where: str) -> PinGroup:
    """One [[pins]] table, checked key by key (the grid is checked by check_groups)."""
    if not isinstance(data, dict):
        raise _error(f"{where} must be a table, got {type(data).__name__}")
    group = PinGroup()
    for name, value in data.items():
        if name not in PIN_KEYS:
            raise _error(f"unknown key {where}.{name}: a [[pins]] table has "
                         f"{', '.join(PIN_KEYS)}")
        at = f"{where}.{name}"
        if name in ("rows", "cols"):
            what = "[first, last], integers (negative counts from the end)"
            setattr(group, name, [_number(v, at, what, integer=True)
                                  for v in _list(value, at, what, 2)])
        elif name == "at":
            what = "[[row, col], ...], integers"
            group.at = [[_number(v, at, what, integer=True) for v in _list(c, at, what, 2)]
                        for c in _list(value, at, what, most=MAX_AT)]
        elif name == "offset":
            group.offset = _offset(value, at)
        elif name == "stiffness":
            s = _number(value, at, "a number with 0 < value ≤ 1")
            if not 0.0 < s <= 1.0:
                raise _error(f"{at} = {short_repr(value)} is not allowed; expected a number "
                             "with 0 < value ≤ 1 (1 holds exactly)")
            group.stiffness = s
        else:
            what = "[[t, dx, dy, dz], ...]: times in s, offsets in m"
            keys = []
            for k in _list(value, at, what, most=MAX_KEYS):
                k = _list(k, at, what, 4)
                t = _number(k[0], at, what)
                if not 0.0 <= t <= MAX_KEY_TIME:
                    raise _error(f"{at}: key time {t:g} s is not allowed; expected 0 ≤ t ≤ "
                                 f"{MAX_KEY_TIME:g}")
                keys.append([t] + _offset(k[1:], at))
            if not keys:
                raise _error(f"{at} = [] is not allowed: give at least one [t, dx, dy, dz] "
                             "key, or leave keys out")
            for (t0, *_), (t1, *_) in zip(keys, keys[1:]):
                if not t1 > t0:
                    raise _error(f"{at}: key times must increase ({t0:g} s is followed by "
                                 f"{t1:g} s)")
            group.keys = keys
    if not (group.rows or group.cols or group.at):
        raise _error(f"{where} holds no particles: choose them with rows and cols "
                     "([first, last]) or at ([[row, col], ...])")
    if group.at and (group.rows or group.cols):
        raise _error(f"{where}: choose particles with rows/cols or with at, not both")
    if group.keys and "offset" in data:
        raise _error(f"{where}: keys give the offset over time; leave out offset (or make "
                     "it the first key)")
    return group


def groups_from_list(value: Any) -> list[PinGroup]:
    if not isinstance(value, list):
        raise _error("pins must be an array of tables ([[pins]])")
    if len(value) > MAX_PIN_GROUPS:
        raise _error(f"pins: {len(value)} groups; at most {MAX_PIN_GROUPS} are allowed")
    return [group_from_dict(g, f"pins[{i}]") for i, g in enumerate(value)]


def group_to_dict(group: PinGroup) -> dict[str, Any]:
    """The table as a scene file writes it: keys left at their default are left out."""
    return {name: getattr(group, name) for name in PIN_KEYS
            if getattr(group, name) != getattr(DEFAULT_GROUP, name)}


def span(pair: list[int], count: int, where: str, axis: str) -> range:
    """The indices an inclusive [first, last] range chooses among `count`."""
    if not pair:
        return range(count)
    first, last = (v + count if v < 0 else v for v in pair)
    for v in (first, last):
        if not 0 <= v < count:
            raise _error(f"{where} = {pair} is outside the sheet: it has {count} {axis} "
                         f"(0 to {count - 1}, or −{count} to −1 from the end)")
    if last < first:
        raise _error(f"{where} = {pair} is empty: the last {axis[:-1]} comes before the first")
    return range(first, last + 1)


def cells(group: PinGroup, rows: int, cols: int, where: str) -> list[tuple[int, int]] | None:
    """The (row, col) cells of `at`, or None for a rows × cols block (see block)."""
    if not group.at:
        return None
    out = []
    for r, c in group.at:
        rr, cc = r + rows if r < 0 else r, c + cols if c < 0 else c
        if not (0 <= rr < rows and 0 <= cc < cols):
            raise _error(f"{where}.at: [{r}, {c}] is outside the sheet of {rows} rows × "
                         f"{cols} columns")
        out.append((rr, cc))
    return out


def block(group: PinGroup, rows: int, cols: int, where: str) -> tuple[range, range]:
    return (span(group.rows, rows, f"{where}.rows", "rows"),
            span(group.cols, cols, f"{where}.cols", "columns"))


def check_groups(groups: list[PinGroup], rows: int, cols: int) -> None:
    """Every group chooses particles inside a sheet of rows × cols."""
    for i, g in enumerate(groups):
        if cells(g, rows, cols, f"pins[{i}]") is None:
            block(g, rows, cols, f"pins[{i}]")


def lowest_offset(groups: list[PinGroup]) -> float:
    """The lowest dy (m) any hard group holds its particles at (0 with none lower)."""
    return min([0.0] + [o[1] for g in groups if g.stiffness == 1.0 for o in g.offsets()])
