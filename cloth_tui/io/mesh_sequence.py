"""`OUT_####.obj` / `.ply`: one mesh file per frame through PyVista's (VTK's) writers, for
tools without USD. Each file is written under a temp name and renamed, so every file that
exists is whole; a killed bake keeps the frames done so far."""

from __future__ import annotations

import contextlib
import os
import re
import secrets
from pathlib import Path

import numpy as np

from ..sim.surface import grid_uv, vertex_normals
from .frames import BakedFrame, SheetFaces

SEQUENCE_SUFFIXES = (".obj", ".ply")
DEFAULT_DIGITS = 4


class BakeIOError(Exception):
    """A bake's file could not be written; one line, fit to show the user."""


def sequence_path(pattern: Path, frame: int) -> Path:
    """`f_####.obj` → `f_0007.obj` for frame 7 (as many digits as #s, at least); a name
    without #s gets `_####` before its suffix."""
    pattern = Path(pattern)
    stem = pattern.stem
    if "#" not in stem:
        stem += "_" + "#" * DEFAULT_DIGITS
    run = max(re.findall(r"#+", stem), key=len)
    name = stem.replace(run, f"{frame:0{len(run)}d}", 1)
    return pattern.with_name(name + pattern.suffix)


def _vtk_faces(triangles: np.ndarray) -> np.ndarray:
    return np.c_[np.full(len(triangles), 3, np.int64), triangles].ravel()


class MeshSequenceWriter:
    def __init__(self, pattern: Path, model):
        import pyvista as pv

        self.pattern = Path(pattern)
        self.suffix = self.pattern.suffix.lower()
        self.faces = SheetFaces(model)
        self.mesh = pv.PolyData(np.asarray(model.rest_positions, dtype=np.float64).copy(),
                                _vtk_faces(self.faces.all))
        # float32: VTK's PLY writer takes no other texture coordinates (and crashes on them)
        self.mesh.active_texture_coordinates = grid_uv(model.nx, model.nz, model.width,
                                                       model.length).astype(np.float32)
        self.paths: list[Path] = []

    def write(self, frame: BakedFrame) -> None:
        x = np.asarray(frame.positions, dtype=np.float64)
        if self.faces.update(frame.alive):  # a tear: its faces go, as the renderer draws it
            self.mesh.cell_data.clear()  # per-face arrays a save left, of the old faces' count
            self.mesh.faces = _vtk_faces(self.faces.triangles)
        self.mesh.points = x
        self.mesh.point_data["Normals"] = vertex_normals(x, self.faces.triangles).astype(
            np.float32)
        self.mesh.point_data.active_normals_name = "Normals"
        path = sequence_path(self.pattern, frame.frame)
        # The temp name keeps the suffix: VTK picks its writer by it.
        tmp = path.with_name(f".{path.stem}.{secrets.token_hex(4)}.part{self.suffix}")
        try:
            self.mesh.save(str(tmp), binary=self.suffix == ".ply")
            os.replace(tmp, path)
        except (OSError, ValueError) as e:
            with contextlib.suppress(OSError):
                os.unlink(tmp)
            raise BakeIOError(f"cannot write {path}: {getattr(e, 'strerror', None) or e}") \
                from None
        self.paths.append(path)

    def close(self) -> None:
        pass  # every frame is already a finished file
