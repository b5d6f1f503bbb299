"""What a wedge runs: the varied keys, their values, every combination as a cell with its
scene, and where each cell sits on the contact sheet. Validated up front through the scene's
own checks, so a bad key or value is one line before any work. No heavy imports."""

from __future__ import annotations

import itertools
import tomllib
from dataclasses import dataclass
from typing import Any

from ..scene import Scene, SceneError
from ..usage import UsageError

MAX_RUNS = 256  # a bigger grid is unreadable as one sheet; split it into several wedges


@dataclass(frozen=True)
class Vary:
    key: str
    values: tuple


@dataclass(frozen=True)
class Cell:
    index: tuple[int, ...]      # one value index per varied key, in --vary order
    values: dict[str, Any]      # key → value of this run
    scene: Scene


def _parse_values(raw: str) -> list:
    """`2,8` / `true` / `[1,0,0],[0,0,1]` / `none,corners`: read as the items of one TOML
    array when that works (vectors keep their commas), else split on commas, each item read
    as TOML or kept as a plain string (as --set does)."""
    try:
        return list(tomllib.loads(f"v = [{raw}]")["v"])
    except (tomllib.TOMLDecodeError, RecursionError, ValueError):
        return [_parse_item(item.strip()) for item in raw.split(",")]


def _parse_item(item: str) -> Any:
    try:
        return tomllib.loads(f"v = {item}")["v"]
    except (tomllib.TOMLDecodeError, RecursionError, ValueError):
        return item


def parse_vary(text: str) -> tuple[str, list]:
    if "=" not in text:
        raise UsageError(f"--vary {text!r}: expected SECTION.KEY=V1,V2,…")
    key, raw = (s.strip() for s in text.split("=", 1))
    if not raw or any(not item.strip() for item in raw.split(",")) and "[" not in raw:
        raise UsageError(f"--vary {text!r}: an empty value; expected SECTION.KEY=V1,V2,…")
    return key, _parse_values(raw)


def plan(base: Scene, varies: list[str]) -> tuple[list[Vary], list[Cell]]:
    """The varied keys (each value checked through the scene) and every combination."""
    out: list[Vary] = []
    for text in varies:
        key, values = parse_vary(text)
        if any(v.key == key for v in out):
            raise UsageError(f"--vary {key}: given twice; list all its values in one --vary")
        checked = []
        for v in values:
            try:  # the scene's own coercion: 2 → 2.0 for a float key, and its error text
                checked.append(base.with_value(key, v).get(key))
            except SceneError as e:
                raise UsageError(f"--vary: {e}") from None
        if len({repr(v) for v in checked}) != len(checked):
            raise UsageError(f"--vary {key}: a value is listed twice")
        out.append(Vary(key, tuple(checked)))
    runs = 1
    for v in out:
        runs *= len(v.values)
    if runs > MAX_RUNS:
        raise UsageError(f"--vary: {runs} combinations; at most {MAX_RUNS} in one wedge")
    cells = []
    for index in itertools.product(*(range(len(v.values)) for v in out)):
        values = {v.key: v.values[i] for v, i in zip(out, index)}
        try:  # keys that constrain each other are checked together
            scene = base.with_values(values)
        except SceneError as e:
            shown = ", ".join(f"{k}={value_text(x)}" for k, x in values.items())
            raise UsageError(f"--vary: the run {shown} is not a valid scene: {e}") from None
        scene.name = base.name
        cells.append(Cell(index, values, scene))
    return out, cells


def value_text(v: Any) -> str:
    if isinstance(v, bool):
        return "true" if v else "false"
    if isinstance(v, float):
        return f"{v:g}"
    if isinstance(v, list):
        return "[" + ",".join(value_text(x) for x in v) + "]"
    return str(v)


def label(key: str, value: Any) -> str:
    return f"{key} = {value_text(value)}"


@dataclass(frozen=True)
class Layout:
    """Where each cell goes: keys with one value are the same in every cell (named in the
    title); of the others, the 1st, 3rd, … run along the columns and the 2nd, 4th, … down the
    rows, the earlier key outside (a block per value) and the later one inside."""
    fixed: list[Vary]
    col_keys: list[Vary]
    row_keys: list[Vary]

    @classmethod
    def of(cls, varies: list[Vary]) -> "Layout":
        grid = [v for v in varies if len(v.values) > 1]
        return cls([v for v in varies if len(v.values) == 1], grid[0::2], grid[1::2])

    @property
    def cols(self) -> int:
        return _count(self.col_keys)

    @property
    def rows(self) -> int:
        return _count(self.row_keys)

    def position(self, varies: list[Vary], cell: Cell) -> tuple[int, int]:
        """(row, column) of a cell."""
        at = {v.key: i for v, i in zip(varies, cell.index)}
        return _mixed(self.row_keys, at), _mixed(self.col_keys, at)


def _count(keys: list[Vary]) -> int:
    n = 1
    for v in keys:
        n *= len(v.values)
    return n


def _mixed(keys: list[Vary], at: dict[str, int]) -> int:
    """Mixed-radix index, the first key most significant."""
    i = 0
    for v in keys:
        i = i * len(v.values) + at[v.key]
    return i
