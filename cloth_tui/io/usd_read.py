"""Reading a USD bake back (what usd_bake writes): the scene it was made from, and per frame
the cloth's points, which of its constraints were intact, and where each object was. For
re-rendering without re-simulating."""

from __future__ import annotations

from pathlib import Path

import numpy as np

from ..scene import SceneError
from ..scene_files import loads
from ..sim.collision.shapes.base import vector
from ..sim.protocols import ObjectPose
from ..usage import UsageError
from . import bake_checks as checks
from .usd_bake import ALIVE_KEY, GRID_KEY, SCENE_KEY, USD_SUFFIXES, missing_usd_message

CLOTH_PATH = "/World/Cloth"
OBJECTS_PATH = "/World/Objects"


def is_usd(path) -> bool:
    return Path(str(path)).suffix.lower() in USD_SUFFIXES


class UsdBake:
    """A bake opened for reading. `frames` are its time codes, in order. Everything read
    from the file is checked once, on opening, every frame included (bake_checks): a bake is
    user input, and a bad value found mid-render or mid-replay would cost the work done."""

    def __init__(self, path: Path):
        message = missing_usd_message()
        if message:
            raise UsageError(message)
        from pxr import Tf

        self.path = Path(path)
        try:
            exists, is_file = self.path.exists(), self.path.is_file()
        except OSError as e:  # a name longer than the file system allows
            raise UsageError(f"{self.path}: {e.strerror}") from None
        if not is_file:  # a FIFO or a device would block or never end
            raise UsageError(f"{self.path}: " + ("not a regular file" if exists else
                                                 "no such file"))
        try:
            with checks.diagnostics_kept_off_the_terminal():
                self._read()
        except Tf.ErrorException as e:  # a value USD itself cannot read
            raise UsageError(f"{self.path}: not a readable cloth-tui bake "
                             f"({checks.usd_reason(e)})") from None
        except UnicodeDecodeError:  # a damaged string, turned into Python's str
            raise UsageError(f"{self.path}: not a readable cloth-tui bake (a text value "
                             "that is not UTF-8)") from None

    def _read(self) -> None:
        from pxr import UsdGeom

        self.stage = stage = checks.open_stage(self.path)
        text = stage.GetRootLayer().customLayerData.get(SCENE_KEY)
        cloth = UsdGeom.Mesh.Get(stage, CLOTH_PATH)
        if text is None or not cloth:
            raise UsageError(f"{self.path}: not a cloth-tui bake (no {CLOTH_PATH} mesh or "
                             f"no scene in its metadata)")
        try:
            self.scene = loads(checks.scene_text(self.path, text), name=self.path.stem)
        except SceneError as e:
            raise UsageError(f"{self.path}: its recorded scene is invalid: {e}") from None
        self.points = cloth.GetPointsAttr()
        self._alive = cloth.GetPrim().GetAttribute(ALIVE_KEY)  # written once the sheet tore
        # (nx, nz); None in a bake made before rectangular sheets (a square one)
        self.grid = _grid_of(self.path, cloth.GetPrim().GetAttribute(GRID_KEY))
        self.frames = checks.time_codes(self.path, self.points.GetTimeSamples())
        if not self.frames:
            raise UsageError(f"{self.path}: the bake holds no frames")
        self.frame_rate = checks.frame_rate(self.path, stage.GetTimeCodesPerSecond())
        self._objects = self._read_objects()
        self._check_frames()

    def _read_objects(self) -> list:
        out = []
        root = self.stage.GetPrimAtPath(OBJECTS_PATH)
        if not root:
            return out
        for prim in root.GetChildren():
            shape = checks.object_shape(self.path, prim)
            if shape is not None:
                out.append((shape, checks.translate_op(self.path, prim)))
        return out

    def _check_frames(self) -> None:
        """Every frame's points (one count for all), intact flags and object centres."""
        count = flags = None
        torn = bool(self._alive) and self._alive.HasAuthoredValue()
        for frame in self.frames:
            count = len(checks.points(self.path, frame, self.points.Get(float(frame)), count))
            if torn:
                flags = len(checks.alive_flags(self.path, frame,
                                               self._alive.Get(float(frame)), flags))
            for _, translate in self._objects:
                if vector(translate.Get(float(frame))) is None:
                    raise UsageError(f"{self.path}: frame {frame} places "
                                     f"{translate.GetPrim().GetPath()} at no finite point")
        self.flag_count = flags  # None: never torn

    def positions(self, frame: int) -> np.ndarray:
        """(N, 3) float64 points of the cloth at this frame (stored as float32)."""
        return np.asarray(self.points.Get(float(frame)), dtype=np.float64)

    def alive(self, frame: int) -> np.ndarray | None:
        """The constraints' intact flags at this frame (model.edges order), or None while
        nothing is torn: what a Snapshot carries, so a replay shows the tear."""
        if not self._alive or not self._alive.HasAuthoredValue():
            return None
        alive = np.asarray(self._alive.Get(float(frame)), dtype=np.uint8)
        return None if alive.all() else alive

    def objects(self, frame: int) -> tuple:
        return tuple(ObjectPose(kind, parameters, tuple(map(float, translate.Get(float(frame)))))
                     for (kind, parameters), translate in self._objects)


def _grid_of(path, attribute) -> tuple[int, int] | None:
    """The bake's recorded (nx, nz), checked as every value read from a bake is."""
    if not attribute or not attribute.HasValue():
        return None
    try:
        nx, nz = (int(v) for v in attribute.Get())
    except (TypeError, ValueError, OverflowError):
        nx = nz = 0
    if not (2 <= nx <= 100_000 and 2 <= nz <= 100_000):
        raise UsageError(f"{path}: its {GRID_KEY} is not two particle counts of at least 2")
    return nx, nz
