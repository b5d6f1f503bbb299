"""Reading a USD bake back (what usd_bake writes): the scene it was made from, and per frame
the cloth's points, which of its constraints were intact, and where each object was. For
re-rendering without re-simulating."""

from __future__ import annotations

from pathlib import Path

import numpy as np

from ..scene import SceneError
from ..scene_files import loads
from ..sim.protocols import ObjectPose
from ..usage import UsageError
from .usd_bake import ALIVE_KEY, GRID_KEY, SCENE_KEY, USD_SUFFIXES, missing_usd_message

CLOTH_PATH = "/World/Cloth"
OBJECTS_PATH = "/World/Objects"


def is_usd(path) -> bool:
    return Path(str(path)).suffix.lower() in USD_SUFFIXES


class UsdBake:
    """A bake opened for reading. `frames` are its time codes, in order."""

    def __init__(self, path: Path):
        message = missing_usd_message()
        if message:
            raise UsageError(message)
        from pxr import Usd, UsdGeom

        self.path = Path(path)
        if not self.path.is_file():
            raise UsageError(f"{self.path}: no such file")
        try:
            stage = Usd.Stage.Open(str(self.path))
        except Exception as e:  # pxr's Tf.ErrorException: a broken or foreign file
            raise UsageError(f"{self.path}: not a readable USD file "
                             f"({str(e).strip().splitlines()[-1] if str(e).strip() else e})"
                             ) from None
        if stage is None:
            raise UsageError(f"{self.path}: not a readable USD file")
        self.stage = stage
        text = stage.GetRootLayer().customLayerData.get(SCENE_KEY)
        cloth = UsdGeom.Mesh.Get(stage, CLOTH_PATH)
        if text is None or not cloth:
            raise UsageError(f"{self.path}: not a cloth-tui bake (no {CLOTH_PATH} mesh or "
                             f"no scene in its metadata)")
        try:
            self.scene = loads(text, name=self.path.stem)
        except SceneError as e:
            raise UsageError(f"{self.path}: its recorded scene is invalid: {e}") from None
        self.points = cloth.GetPointsAttr()
        self._alive = cloth.GetPrim().GetAttribute(ALIVE_KEY)  # written once the sheet tore
        grid = cloth.GetPrim().GetAttribute(GRID_KEY)
        # (nx, nz); None in a bake made before rectangular sheets (a square one)
        self.grid = tuple(int(v) for v in grid.Get()) if grid and grid.HasValue() else None
        self.frames = [int(round(t)) for t in self.points.GetTimeSamples()]
        if not self.frames:
            raise UsageError(f"{self.path}: the bake holds no frames")
        self.frame_rate = float(stage.GetTimeCodesPerSecond())
        self._objects = self._read_objects()

    def _read_objects(self) -> list:
        from pxr import UsdGeom

        out = []
        root = self.stage.GetPrimAtPath(OBJECTS_PATH)
        if not root:
            return out
        for prim in root.GetChildren():
            get = prim.GetAttribute
            kind = get("cloth_tui:type").Get()
            if kind is None:
                continue
            shape = dict(type=str(kind), radius=float(get("cloth_tui:radius").Get()),
                         size=tuple(get("cloth_tui:size").Get()),
                         normal=tuple(get("cloth_tui:normal").Get()),
                         axis=tuple(get("cloth_tui:axis").Get()),
                         length=float(get("cloth_tui:length").Get()))
            translate = UsdGeom.Xformable(prim).GetOrderedXformOps()[0].GetAttr()
            out.append((shape, translate))
        return out

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
        return tuple(ObjectPose(center=tuple(map(float, translate.Get(float(frame)))), **shape)
                     for shape, translate in self._objects)
