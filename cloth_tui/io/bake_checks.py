"""A bake given to `render` or the replay app is user input: every value read from it is
checked here, and anything a cloth-tui bake never holds is refused in one line (UsageError).

- Composition arcs (sublayers, references, payloads, value clips) are refused before the
  stage is composed: USD followed them to any file on disk, printed its multi-line warnings,
  and blocked for ever on a FIFO. The root layer alone is opened first and inspected.
- USD's diagnostics go to a scratch file while the bake is opened, not to the terminal.
- The frame rate, the time codes, the objects' attributes and every frame's points, intact
  flags and object centres are checked for type, shape and finiteness.
"""

from __future__ import annotations

import contextlib
import os
import re
import sys
import tempfile
from pathlib import Path

import numpy as np

from ..sim.collision.shapes import SHAPES
from ..sim.collision.shapes.base import MAX_LENGTH, ShapeValueError, finite
from ..usage import UsageError

MIN_FRAME_RATE, MAX_FRAME_RATE = 1.0, 10000.0  # the scene's behavior.frame_rate range
MAX_TIME_CODE = 2 ** 31 - 1
ARC_FIELDS = ("references", "payload", "clips", "clipSets")


@contextlib.contextmanager
def diagnostics_kept_off_the_terminal():
    """Point file descriptor 2 at a scratch file for the `with` (USD's C++ diagnostics write
    there directly, not through Python). Used while a bake is opened, before any other
    thread (the app's screen, on stderr too) runs."""
    try:
        sys.stderr.flush()
        saved = os.dup(2)
    except (OSError, ValueError):  # no descriptor 2 (a detached process): nothing to keep
        yield
        return
    with tempfile.TemporaryFile() as scratch:
        os.dup2(scratch.fileno(), 2)
        try:
            yield
        finally:
            with contextlib.suppress(OSError, ValueError):
                sys.stderr.flush()
            os.dup2(saved, 2)
            os.close(saved)


def open_stage(path: Path):
    """The bake's stage, composed from its root layer only, once that layer is known to
    have no composition arcs."""
    from pxr import Sdf, Usd

    try:
        layer = Sdf.Layer.FindOrOpen(str(path))
    except Exception as e:  # pxr's Tf.ErrorException: a broken or foreign file
        raise UsageError(f"{path}: not a readable USD file ({usd_reason(e)})") from None
    if layer is None:
        raise UsageError(f"{path}: not a readable USD file")
    arc = composition_arc(layer)
    if arc is not None:
        raise UsageError(f"{path}: {arc}; a cloth-tui bake has none, and a bake is opened "
                         "without following them")
    try:
        stage = Usd.Stage.Open(layer, load=Usd.Stage.LoadNone)
    except Exception as e:
        raise UsageError(f"{path}: not a readable USD file ({type(e).__name__})") from None
    if stage is None:
        raise UsageError(f"{path}: not a readable USD file")
    return stage


def usd_reason(e: BaseException) -> str:
    """The gist of a pxr error: its message without the C++ function, file and line."""
    text = " ".join(str(e).split())
    m = re.search(r"Error in '[^']*' at line \d+ in file \S+ : '?(.*?)'?$", text)
    return (m.group(1) if m else text or type(e).__name__)[:200]


def composition_arc(layer) -> str | None:
    """What in the layer would pull in other files, said in a few words, or None."""
    from pxr import Sdf

    if layer.subLayerPaths:
        return f"it sublayers {list(layer.subLayerPaths)[0]!r}"
    found: list[str] = []

    def visit(path):
        if found or not (path.IsPrimPath() or path.IsPrimVariantSelectionPath()):
            return
        spec = layer.GetPrimAtPath(path)
        if spec is None:
            return
        for field in ARC_FIELDS:
            if spec.HasInfo(field):
                found.append(f"{path} has {field}")
                return

    layer.Traverse(Sdf.Path.absoluteRootPath, visit)
    return found[0] if found else None


def frame_rate(path: Path, value) -> float:
    rate = finite(value)
    if rate is None or not MIN_FRAME_RATE <= rate <= MAX_FRAME_RATE:
        raise UsageError(f"{path}: timeCodesPerSecond = {value!r}; a bake's frame rate is "
                         f"{MIN_FRAME_RATE:g}..{MAX_FRAME_RATE:g} frames per second")
    return rate


def time_codes(path: Path, samples) -> list[int]:
    """The frames (time codes), whole numbers in 0..MAX_TIME_CODE, in order."""
    frames = []
    for t in samples:
        f = finite(t)
        if f is None or f != round(f) or not 0 <= f <= MAX_TIME_CODE:
            raise UsageError(f"{path}: a time code of {t!r}; a bake's frames are whole "
                             f"numbers 0..{MAX_TIME_CODE}")
        frames.append(int(f))
    return frames


def scene_text(path: Path, value) -> str:
    if not isinstance(value, str):
        raise UsageError(f"{path}: its recorded scene is a {type(value).__name__}, not the "
                         "text of a scene file")
    return value


def object_shape(path: Path, prim) -> tuple[str, dict] | None:
    """An object prim's type and its shape's parameters, as recorded (cloth_tui:type, then
    the shape's own attributes and prim), checked; None for a prim that is not a cloth-tui
    object (no cloth_tui:type)."""
    where = f"{path}: {prim.GetPath()}"
    kind = _attr(prim, "type")
    if kind is None:
        return None
    if not isinstance(kind, str) or kind not in SHAPES:
        raise UsageError(f"{where}: cloth_tui:type = {str(kind)[:40]!r}; expected one of "
                         f"{', '.join(SHAPES)}")
    try:
        return kind, SHAPES[kind].read_usd(prim)
    except ShapeValueError as e:
        raise UsageError(f"{where}: {e}") from None


def translate_op(path: Path, prim):
    """The attribute of the object's translate, the first of its transform operations."""
    from pxr import UsdGeom

    ops = UsdGeom.Xformable(prim).GetOrderedXformOps()
    if not ops or ops[0].GetOpType() != UsdGeom.XformOp.TypeTranslate:
        raise UsageError(f"{path}: {prim.GetPath()} has no translate, where a cloth-tui bake "
                         "places each object")
    return ops[0].GetAttr()


def points(path: Path, frame: int, value, count: int | None) -> np.ndarray:
    try:
        x = np.asarray(value, dtype=np.float64)
    except (TypeError, ValueError):
        x = np.zeros((0,))
    if x.ndim != 2 or x.shape[1] != 3 or len(x) == 0 or (count is not None and len(x) != count):
        raise UsageError(f"{path}: frame {frame} has {x.shape[0] if x.ndim else 0} cloth "
                         f"points" + (f", the first frame {count}" if count else "") +
                         " (or they are not 3-vectors)")
    if not np.all(np.isfinite(x)) or np.abs(x).max() > MAX_LENGTH:
        raise UsageError(f"{path}: frame {frame} has cloth points that are not finite or "
                         f"beyond ±{MAX_LENGTH:g} m")
    return x


def alive_flags(path: Path, frame: int, value, count: int | None) -> np.ndarray:
    try:
        a = np.asarray(value)
    except (TypeError, ValueError):
        a = np.zeros((0, 0))
    if a.ndim != 1 or (count is not None and len(a) != count) or not np.isin(a, (0, 1)).all():
        raise UsageError(f"{path}: frame {frame}'s cloth_tui:alive is not one 0/1 flag per "
                         "constraint" + (f" ({count})" if count is not None else ""))
    return a.astype(np.uint8)


def _attr(prim, name: str):
    attr = prim.GetAttribute(f"cloth_tui:{name}")
    return attr.Get() if attr else None


