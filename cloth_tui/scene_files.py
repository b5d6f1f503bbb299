"""Scene files and overrides: TOML text ↔ Scene, loading by path or built-in name, atomic
saving, and `--set SECTION.KEY=VALUE` overrides. The schema and its checks are in scene.py."""

from __future__ import annotations

import os
import tomllib
from pathlib import Path
from typing import Any

from .materials.section import is_material_key
from .resources import builtin_scenes
from .safe_text import escape_controls
from .scene import Scene, SceneError, from_dict, split_key, to_dict
from .user_values import PathProblem, short_repr, user_path
from .util import atomic_write


def toml_value(v: Any) -> str:
    if isinstance(v, bool):
        return "true" if v else "false"
    if isinstance(v, (int, float)):
        return repr(v)
    if isinstance(v, str):
        return '"' + v.replace("\\", "\\\\").replace('"', '\\"') + '"'
    if isinstance(v, list):
        return "[" + ", ".join(toml_value(x) for x in v) + "]"
    raise TypeError(f"cannot write {type(v).__name__} to TOML")


def dumps(scene: Scene) -> str:
    # A comment cannot hold control characters (a newline in a file's name would end it).
    lines = [f"# cloth-tui scene: {escape_controls(scene.name)}"]
    for section, values in to_dict(scene).items():
        if section in ("objects", "pins"):
            for table in values:
                lines += ["", f"[[{section}]]"] + [f"{k} = {toml_value(v)}"
                                                   for k, v in table.items()]
        else:
            lines += ["", f"[{section}]"] + [f"{k} = {toml_value(v)}" for k, v in values.items()]
    return "\n".join(lines) + "\n"


def loads(text: str, name: str = "scene") -> Scene:
    return from_dict(_parse_toml(text, name), name)


def _parse_toml(text: str, where: str) -> dict:
    try:
        return tomllib.loads(text)
    except tomllib.TOMLDecodeError as e:
        raise SceneError(f"{where}: TOML syntax error: {e}") from None
    except RecursionError:  # thousands of nested arrays or inline tables
        raise SceneError(f"{where}: arrays or tables nested too deeply") from None
    except ValueError:  # an integer past Python's 4300-digit conversion limit
        raise SceneError(f"{where}: an integer with too many digits") from None


def load(ref: str | os.PathLike) -> Scene:
    """Load a scene from a path, or by the name of a built-in scene."""
    path = Path(ref)
    if not path.suffix and str(ref) in builtin_scenes():
        path = builtin_scenes()[str(ref)]
    try:
        is_file = path.is_file()
    except OSError as e:  # a name longer than the file system allows
        raise SceneError(f"scene {short_repr(str(ref))}: {e.strerror}") from None
    if not is_file:
        names = ", ".join(builtin_scenes())
        raise SceneError(f"scene {str(ref)!r} not found: not a file, nor a built-in scene "
                         f"({names})")
    try:
        raw = path.read_bytes()
        text = raw.decode("utf-8")
    except UnicodeDecodeError:
        raise SceneError(f"{path}: not a UTF-8 text file") from None
    except OSError as e:
        raise SceneError(f"{path}: cannot read: {e.strerror}") from None
    scene = loads(text, name=path.stem)
    for k, o in enumerate(scene.objects):  # a mesh's path is relative to the scene file
        if not o.path:
            continue
        try:
            absolute = user_path(o.path).is_absolute()
        except PathProblem as e:
            raise SceneError(f"objects[{k}].path = {short_repr(o.path)}: {e}") from None
        if not absolute:
            o.path = str(path.parent.resolve() / o.path)
    return scene


def save(scene: Scene, path: str | os.PathLike) -> Path:
    """Write atomically (util.atomic_write), with the permissions the umask gives."""
    path = Path(path)
    text = dumps(scene)
    try:
        path.parent.mkdir(parents=True, exist_ok=True)
        with atomic_write(path, "w", encoding="utf-8") as fh:
            fh.write(text)
    except OSError as e:
        raise SceneError(f"cannot write {path}: {e.strerror}") from None
    return path


def parse_override(text: str) -> tuple[str, Any]:
    """`section.key=value`: the value is read as TOML, or as a bare string if that fails."""
    if not isinstance(text, str) or "=" not in text:
        raise SceneError(f"--set {text!r}: expected SECTION.KEY=VALUE")
    dotted, raw = text.split("=", 1)
    dotted, raw = dotted.strip(), raw.strip()
    # `pins=[{...}, ...]` sets the whole [[pins]] array; material keys: materials/section.py
    if dotted != "pins" and not is_material_key(dotted):
        split_key(dotted)
    if raw == "":
        raise SceneError(f"--set {text!r}: missing value after '='")
    try:
        value = tomllib.loads(f"v = {raw}")["v"]
    except tomllib.TOMLDecodeError:
        value = raw
    except RecursionError:
        raise SceneError(f"--set {dotted}: arrays or tables nested too deeply") from None
    except ValueError:  # an integer past Python's 4300-digit conversion limit
        raise SceneError(f"--set {dotted}: an integer with too many digits") from None
    return dotted, value


def apply_overrides(scene: Scene, overrides: list[str] | None) -> Scene:
    return scene.with_values(dict(parse_override(text) for text in overrides or []))
