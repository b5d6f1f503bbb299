"""Hostile USD bakes made from a real one: each mutation is what a damaged or crafted file
could hold (for the tests and tools/fuzz_files.py)."""

from __future__ import annotations

import os
from pathlib import Path

import numpy as np

OBJECT = "/World/Objects/Object_0"


def _stage(path: Path):
    from pxr import Usd
    return Usd.Stage.Open(str(path))


def _save(stage, out: Path) -> Path:
    stage.GetRootLayer().Export(str(out))
    return out


def frame_rate(src: Path, out: Path, rate: float) -> Path:
    stage = _stage(src)
    stage.SetTimeCodesPerSecond(rate)
    return _save(stage, out)


def drop_attribute(src: Path, out: Path, name: str) -> Path:
    stage = _stage(src)
    stage.GetPrimAtPath(OBJECT).RemoveProperty(f"cloth_tui:{name}")
    return _save(stage, out)


def object_value(src: Path, out: Path, name: str, value, type_name: str) -> Path:
    """Give an object's cloth_tui attribute another value (and type)."""
    from pxr import Sdf
    stage = _stage(src)
    prim = stage.GetPrimAtPath(OBJECT)
    prim.RemoveProperty(f"cloth_tui:{name}")
    prim.CreateAttribute(f"cloth_tui:{name}", getattr(Sdf.ValueTypeNames, type_name),
                         custom=True).Set(value)
    return _save(stage, out)


def recorded_scene(src: Path, out: Path, value) -> Path:
    stage = _stage(src)
    layer = stage.GetRootLayer()
    layer.customLayerData = {**layer.customLayerData, "cloth_tui:scene": value}
    return _save(stage, out)


def alive_flags(src: Path, out: Path, count: int, last_count: int, frame: float = 2.0
                ) -> Path:
    """Torn flags of `count` at `frame`, and all intact, of `last_count`, at the last frame
    (4): a check of the last frame alone sees nothing torn."""
    from pxr import Sdf, UsdGeom, Vt
    stage = _stage(src)
    prim = UsdGeom.Mesh.Get(stage, "/World/Cloth").GetPrim()
    attr = prim.CreateAttribute("cloth_tui:alive", Sdf.ValueTypeNames.UCharArray, custom=True)
    attr.Set(Vt.UCharArray.FromNumpy(np.ones(last_count, np.uint8)), 1.0)
    flags = np.ones(count, np.uint8)
    flags[::2] = 0
    attr.Set(Vt.UCharArray.FromNumpy(flags), frame)
    attr.Set(Vt.UCharArray.FromNumpy(np.ones(last_count, np.uint8)), 4.0)
    return _save(stage, out)


def points(src: Path, out: Path, frame: float, value: np.ndarray) -> Path:
    from pxr import UsdGeom, Vt
    stage = _stage(src)
    UsdGeom.Mesh.Get(stage, "/World/Cloth").GetPointsAttr().Set(
        Vt.Vec3fArray.FromNumpy(value.astype(np.float32)), frame)
    return _save(stage, out)


def with_arc(src: Path, out: Path, kind: str, target: Path) -> Path:
    """A sublayer, reference or payload to `target` (which may be a FIFO), edited in the
    layer alone: a stage would compose it, and open the FIFO."""
    from pxr import Sdf
    layer = Sdf.Layer.CreateAnonymous(".usda")
    layer.TransferContent(Sdf.Layer.FindOrOpen(str(src)))
    if kind == "sublayer":
        layer.subLayerPaths.append(str(target))
    else:
        spec = Sdf.CreatePrimInLayer(layer, "/World/Extra")
        spec.specifier = Sdf.SpecifierDef
        if kind == "reference":
            spec.referenceList.Prepend(Sdf.Reference(str(target)))
        else:
            spec.payloadList.Prepend(Sdf.Payload(str(target)))
    layer.Export(str(out))
    return out


def fifo(folder: Path, name: str = "pipe.usda") -> Path:
    path = folder / name
    os.mkfifo(path)
    return path
