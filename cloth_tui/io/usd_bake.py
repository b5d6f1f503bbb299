"""A bake as a USD stage (Pixar's usd-core, the optional extra `[usd]`).

    /World                 Xform, the default prim
      Cloth                Mesh: faces, UVs (primvars:st), time-sampled points, normals, extent;
                           cloth_tui:grid, the particle grid's (nx, nz): points are nz rows
                           of nx (absent from bakes made before rectangular sheets: those
                           are square); on a torn sheet also time-sampled faces (those with
                           no torn edge, a sample where they change) and cloth_tui:alive (the
                           constraints' intact flags, for reading the bake back)
      Ground               Mesh: a quad at the floor's height (when the scene has a floor)
      Objects/Object_k     Xform: translate (time-sampled once the object moves) and the exact
                           shape as cloth_tui:* attributes, for reading the bake back
        Shape              the shape's own prim (sim/shapes/: Sphere, Cube (scaled), Capsule
                           (oriented), Mesh: a plane's quad or a mesh's triangles, ...)

Time code k is frame k (from 1), timeCodesPerSecond = framesPerSecond = the scene's frame
rate, metres (metersPerUnit = 1), y up. The layer's customLayerData holds the scene's TOML, so
a bake says how it was made (and `cloth-tui render` can redraw it).

Crash safety: the stage lives in memory and is exported under a temp name beside the target
and renamed over it every SAVE_INTERVAL_S of wall time (or SAVE_SHARE⁻¹ times as long as the
last save took, when saves grow slow on a long bake) and at the end; each save is a whole
stage with its end time at its last frame, so a SIGKILL leaves the frames of the last save,
readable. A temp file a SIGKILL left goes at the next bake to that name (part_files.py).
When the disk fills, the file keeps its last save and the error says the disk is full.
"""

from __future__ import annotations

import contextlib
import os
import time
from pathlib import Path

import numpy as np

from .. import scene_files as scene_io
from ..sim.collision.shapes import shape_of
from ..sim.collision.shapes.plane import quad
from ..sim.collision.surface import grid_uv, vertex_normals
from .frames import BakedFrame, SheetFaces
from .mesh_sequence import BakeIOError
from .part_files import disk_full, part_path, remove_stale_parts

USD_SUFFIXES = (".usd", ".usdc", ".usda")
SAVE_INTERVAL_S = 1.0   # wall time between saves: what a SIGKILL can lose, at least
SAVE_SHARE = 0.2        # at most this share of the wall time goes to saving
GROUND_HALF = 5.0       # m: half the side of the ground quad
SCENE_KEY = "cloth_tui:scene"
ALIVE_KEY = "cloth_tui:alive"  # the cloth's intact flags, on a torn sheet (model.edges order)
GRID_KEY = "cloth_tui:grid"    # (nx, nz): particles along x (a row) and along z
VERSION_KEY = "cloth_tui:format"
FORMAT_VERSION = 1


def missing_usd_message() -> str | None:
    """None if usd-core can be imported, else the one line that says how to get it."""
    try:
        import pxr.Usd  # noqa: F401
    except ImportError:
        return ("USD needs Pixar's usd-core, which is not installed: "
                "pip install 'cloth-tui[usd]' (or: pip install usd-core)")
    return None


def _hex_color(text: str) -> tuple[float, float, float]:
    t = text.lstrip("#")
    return tuple(int(t[i:i + 2], 16) / 255.0 for i in (0, 2, 4))


class UsdBakeWriter:
    def __init__(self, path: Path, scene, model):
        from pxr import Gf, Sdf, Usd, UsdGeom, Vt

        self.Gf, self.Sdf, self.Usd, self.UsdGeom, self.Vt = Gf, Sdf, Usd, UsdGeom, Vt
        self.path = Path(path)
        self.scene = scene
        self.faces = SheetFaces(model)
        self.stage = Usd.Stage.CreateInMemory()
        stage = self.stage
        UsdGeom.SetStageUpAxis(stage, UsdGeom.Tokens.y)
        UsdGeom.SetStageMetersPerUnit(stage, 1.0)
        rate = float(scene.behavior.frame_rate)
        stage.SetTimeCodesPerSecond(rate)
        stage.SetFramesPerSecond(rate)
        stage.SetStartTimeCode(1)
        stage.SetEndTimeCode(1)
        layer = stage.GetRootLayer()
        layer.customLayerData = {SCENE_KEY: scene_io.dumps(scene),
                                 VERSION_KEY: FORMAT_VERSION}
        world = UsdGeom.Xform.Define(stage, "/World")
        stage.SetDefaultPrim(world.GetPrim())

        self.cloth = UsdGeom.Mesh.Define(stage, "/World/Cloth")
        self.cloth.CreateSubdivisionSchemeAttr(UsdGeom.Tokens.none)  # a polygon mesh
        self.cloth.CreateFaceVertexCountsAttr(Vt.IntArray([3] * len(self.faces.all)))
        self.cloth.CreateFaceVertexIndicesAttr(Vt.IntArray(self.faces.all.ravel().tolist()))
        self.cloth.CreateDoubleSidedAttr(True)
        self.cloth.SetNormalsInterpolation(UsdGeom.Tokens.vertex)
        st = UsdGeom.PrimvarsAPI(self.cloth).CreatePrimvar(
            "st", Sdf.ValueTypeNames.TexCoord2fArray, UsdGeom.Tokens.vertex)
        st.Set(Vt.Vec2fArray.FromNumpy(
            grid_uv(model.nx, model.nz, model.width, model.length).astype(np.float32)))
        self.cloth.GetPrim().CreateAttribute(GRID_KEY, Sdf.ValueTypeNames.Int2,
                                             custom=True).Set(Gf.Vec2i(model.nx, model.nz))
        self.cloth.CreateDisplayColorPrimvar(UsdGeom.Tokens.constant).Set(
            [Gf.Vec3f(*_hex_color(scene.appearance.cloth_color))])
        if scene.scene.floor:
            self._define_ground()
        UsdGeom.Xform.Define(stage, "/World/Objects")
        self.objects: list = []   # (translate op, first centre, centres so far, moving)
        self.alive_attr = None  # cloth_tui:alive, made when the sheet first tears
        self.frames = 0
        self.first_frame: int | None = None
        self.last_frame = 0
        self._saved_at = time.monotonic()
        self._save_s = 0.0  # how long the last save took
        self.saved_frames = 0  # frames in the file on disk
        self._export_found_disk_full = False
        remove_stale_parts(self.path)

    # -- the still parts ------------------------------------------------------------------
    def _define_ground(self) -> None:
        UsdGeom, Vt = self.UsdGeom, self.Vt
        s = self.scene.scene
        half = GROUND_HALF * max(1.0, self.scene.cloth.extent())
        ground = UsdGeom.Mesh.Define(self.stage, "/World/Ground")
        corners = quad((0.0, s.floor_height, 0.0), (0.0, 1.0, 0.0), half)
        ground.CreatePointsAttr(Vt.Vec3fArray.FromNumpy(corners.astype(np.float32)))
        ground.CreateFaceVertexCountsAttr(Vt.IntArray([4]))
        ground.CreateFaceVertexIndicesAttr(Vt.IntArray([0, 1, 2, 3]))
        ground.CreateSubdivisionSchemeAttr(UsdGeom.Tokens.none)
        ground.CreateDisplayColorPrimvar(UsdGeom.Tokens.constant).Set(
            [self.Gf.Vec3f(*_hex_color(self.scene.appearance.ground_color))])

    def _define_object(self, k: int, pose) -> None:
        """The object's Xform (its translate, and its shape's parameters as cloth_tui:*
        attributes, what a bake reads back) and its shape's prim, `Shape`."""
        shape = shape_of(pose.type)  # an unregistered type raises: never another's prim
        xform = self.UsdGeom.Xform.Define(self.stage, f"/World/Objects/Object_{k}")
        translate = xform.AddTranslateOp()
        translate.Set(self.Gf.Vec3d(*pose.center))
        shape.write_usd_parameters(self, xform.GetPrim(), pose.parameters)
        shape.define_usd(self, self.stage, f"/World/Objects/Object_{k}/Shape", pose.parameters)
        centre = tuple(map(float, pose.center))
        self.objects.append([translate, centre, [centre], False])

    # -- frames ---------------------------------------------------------------------------
    def write(self, frame: BakedFrame) -> None:
        Gf, Vt = self.Gf, self.Vt
        x = np.asarray(frame.positions, dtype=np.float64)
        code = float(frame.frame)
        if self.first_frame is None:
            self.first_frame = frame.frame
        if self.faces.update(frame.alive):
            self._write_faces(frame)
        self.cloth.GetPointsAttr().Set(Vt.Vec3fArray.FromNumpy(x.astype(np.float32)), code)
        normals = vertex_normals(x, self.faces.triangles).astype(np.float32)
        self.cloth.GetNormalsAttr().Set(Vt.Vec3fArray.FromNumpy(normals), code)
        lo, hi = x.min(axis=0), x.max(axis=0)
        self.cloth.GetExtentAttr().Set(Vt.Vec3fArray([Gf.Vec3f(*lo), Gf.Vec3f(*hi)]), code)
        for k, pose in enumerate(frame.objects):
            if k == len(self.objects):
                self._define_object(k, pose)
            self._place_object(k, tuple(map(float, pose.center)), frame.frame)
        self.frames += 1
        self.last_frame = frame.frame
        if time.monotonic() - self._saved_at >= max(SAVE_INTERVAL_S,
                                                    self._save_s / SAVE_SHARE):
            self.save()

    def _write_faces(self, frame: BakedFrame) -> None:
        """Samples of the faces and the intact flags from this frame on. Once an attribute
        has samples its default no longer shows, so the first change also samples the whole
        sheet at the bake's first frame, when it came later."""
        intact = np.ones(len(self.faces.model.edges), np.uint8)
        if self.alive_attr is None:
            self.alive_attr = self.cloth.GetPrim().CreateAttribute(
                ALIVE_KEY, self.Sdf.ValueTypeNames.UCharArray, custom=True)
            if frame.frame > self.first_frame:
                self._set_faces(self.faces.all, intact, float(self.first_frame))
        alive = intact if frame.alive is None else np.asarray(frame.alive, dtype=np.uint8)
        self._set_faces(self.faces.triangles, alive, float(frame.frame))

    def _set_faces(self, triangles: np.ndarray, alive: np.ndarray, code: float) -> None:
        Vt = self.Vt
        self.cloth.GetFaceVertexCountsAttr().Set(Vt.IntArray([3] * len(triangles)), code)
        self.cloth.GetFaceVertexIndicesAttr().Set(Vt.IntArray(triangles.ravel().tolist()), code)
        self.alive_attr.Set(Vt.UCharArray.FromNumpy(alive), code)

    def _place_object(self, k: int, centre: tuple, frame: int) -> None:
        """A still object keeps one (default) translate; once it moves, every frame so far
        gets a time sample."""
        entry = self.objects[k]
        op, first, centres, moving = entry
        if len(centres) < frame:
            centres.append(centre)
        if not moving and centre != first:
            entry[3] = moving = True
            start = frame - len(centres) + 1
            for i, c in enumerate(centres):
                op.Set(self.Gf.Vec3d(*c), float(start + i))
        elif moving:
            op.Set(self.Gf.Vec3d(*centre), float(frame))

    # -- saving ---------------------------------------------------------------------------
    def save(self) -> None:
        """The whole stage, exported beside the target and renamed over it. On a full
        disk, the first frames, as many as fit, before the error says so."""
        started = time.monotonic()
        self.stage.SetEndTimeCode(max(1, self.last_frame))
        try:
            self._export(self.stage.GetRootLayer())
        except Exception as e:  # noqa: BLE001 - pxr raises its own Tf.ErrorException
            lines = str(e).strip().splitlines()
            reason = getattr(e, "strerror", None) or (lines[-1] if lines else type(e).__name__)
            if self._export_found_disk_full:
                self._save_what_fits()
                kept = (f"it keeps the first {self.saved_frames} frames"
                        if self.saved_frames else "nothing was saved")
                reason = f"the disk is full ({kept})"  # USD says only "Corrupt asset"
            raise BakeIOError(f"cannot write {self.path}: {reason}") from None
        self.saved_frames = self.frames
        self._saved_at = time.monotonic()
        self._save_s = self._saved_at - started

    def _export(self, layer) -> None:
        """`layer` written under a temp name, synced and renamed over the target; on
        failure the temp is removed and the target left as it was."""
        tmp = part_path(self.path)
        self._export_found_disk_full = False
        try:
            if not layer.Export(str(tmp)):
                raise OSError(f"USD could not export {tmp}")
            fd = os.open(tmp, os.O_RDONLY)
            try:
                os.fsync(fd)
            finally:
                os.close(fd)
            os.replace(tmp, self.path)
        except BaseException:
            self._export_found_disk_full = disk_full(tmp.parent)  # before the temp goes
            with contextlib.suppress(OSError):
                os.unlink(tmp)
            raise

    def _save_what_fits(self) -> None:
        """The most frames that fit beside the last save, found by halving: each try is
        a copy of the stage without the frames after its last (the stage itself keeps
        them all)."""
        fits, too_many = self.saved_frames, self.frames
        while too_many - fits > 1:
            count = (fits + too_many) // 2
            last = float((self.first_frame or 1) + count - 1)
            trial = self.Sdf.Layer.CreateAnonymous(self.path.suffix)
            trial.TransferContent(self.stage.GetRootLayer())
            _drop_samples_after(trial, last)
            trial.endTimeCode = last
            try:
                self._export(trial)
            except Exception:  # noqa: BLE001 - as in save: this many do not fit either
                too_many = count
            else:
                fits = count
        self.saved_frames = fits

    def close(self) -> None:
        self.save()


def _drop_samples_after(layer, last: float) -> None:
    """Removes every time sample after `last` from `layer`."""
    paths = []
    layer.Traverse(layer.pseudoRoot.path, lambda path: paths.append(path)
                   if path.IsPropertyPath() else None)
    for path in paths:
        for t in layer.ListTimeSamplesForPath(path):
            if t > last:
                layer.EraseTimeSample(path, t)
