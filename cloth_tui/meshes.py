"""Mesh colliders' data: a surface read from a file and the signed-distance grid around it.

This module takes the triangles of an STL, OBJ, PLY or VTK file from mesh_files (which checks
them before any VTK code sees them) and samples VTK's implicit distance
(vtkImplicitPolyDataDistance) on a regular grid. PyVista is imported only inside the
functions that need it, so the physics (cloth_tui.sim), which receives the results as numpy
arrays, loads no GL or VTK module unless a scene has a mesh.

The grid's cell is half the cloth's particle spacing (a contact never lands more than a
quarter spacing from a sample), but at least the extent of the mesh and its skin / MAX_CELLS,
so a large mesh (or a thick skin) under a fine sheet stays at most (MAX_CELLS + 2·PAD_CELLS)³
samples (about a second to build). It is padded by
the collision skin and PAD_CELLS cells on every side; beyond it, the distance is taken as
far (no contact). Results are cached per (file, its size and mtime, transform, cell).

The surface must be closed (no boundary or non-manifold edge): its distance is signed,
negative inside, by a ray-casting inside test. An open surface is refused with one line. (An
unsigned or face-signed distance was tried for open ones: the sign flips across the plane
of a boundary edge, a phantom wall beyond it that threw the sheet upward, and the unsigned
distance lets a particle through that crosses the skin within a substep.)
"""

from __future__ import annotations

import functools
import math
from collections.abc import Callable
from dataclasses import dataclass

import numpy as np

from .scene_keys import SceneError
from .user_values import PathProblem, short_repr, user_path

SUFFIXES = (".stl", ".obj", ".ply", ".vtk", ".vtp")
MAX_FILE_BYTES = 200 * 1024 * 1024   # a larger file is refused before it is read
MAX_TRIANGLES = 1_000_000            # a larger surface is refused
# All of a scene's mesh objects together: each object's grid costs time in proportion to its
# triangles (seconds per few hundred thousand), so this bounds the start-up to seconds.
MAX_SCENE_TRIANGLES = 2_000_000
MAX_CELLS = 64                       # per axis of the distance grid
PAD_CELLS = 3                        # grid cells beyond the skin on every side


# Set by a command that shows progress on a terminal: called with one line (no newline)
# before each distance grid is built, the slow part of starting a scene with meshes.
progress: Callable[[str], None] | None = None


@dataclass(frozen=True)
class MeshSurface:
    """Triangles of a mesh in the object's frame (scaled and rotated, centred on its origin:
    the object's `center` places it). `key` names the file and transform, for the renderer."""
    key: str
    vertices: np.ndarray  # (V, 3) float64, m
    faces: np.ndarray     # (F, 3) int64


@dataclass(frozen=True)
class MeshField:
    """Distance samples on a regular grid in the object's frame: sample (i, j, k) is at
    origin + cell·(i, j, k). `gradient` is the distance's central-difference gradient."""
    surface: MeshSurface
    origin: np.ndarray    # (3,) m
    cell: float           # m
    distance: np.ndarray  # (nx, ny, nz) m, negative inside
    gradient: np.ndarray  # (nx, ny, nz, 3)


def rotation_matrix(degrees) -> np.ndarray:
    """Rotation by degrees about x, then y, then z (fixed axes): R = Rz·Ry·Rx."""
    ax, ay, az = (math.radians(float(v)) for v in degrees)
    cx, sx, cy, sy, cz, sz = (math.cos(ax), math.sin(ax), math.cos(ay), math.sin(ay),
                              math.cos(az), math.sin(az))
    rx = np.array([[1, 0, 0], [0, cx, -sx], [0, sx, cx]])
    ry = np.array([[cy, 0, sy], [0, 1, 0], [-sy, 0, cy]])
    rz = np.array([[cz, -sz, 0], [sz, cz, 0], [0, 0, 1]])
    return rz @ ry @ rx


def check_scene_meshes(objects) -> None:
    """Refuse, before any grid is built, mesh objects that hold more than MAX_SCENE_TRIANGLES
    triangles in all (each object counts: each gets its own grid). `objects` are
    (where, SceneObject) pairs."""
    total = 0
    for where, obj in objects:
        total += _read_surface(*_file_key(obj.path, where), where).n_cells
        if total > MAX_SCENE_TRIANGLES:
            raise SceneError(f"{where}: the scene's mesh objects hold {total} triangles up to "
                             f"this one; at most {MAX_SCENE_TRIANGLES} in all are allowed "
                             "(fewer or simpler meshes)")


def field_for(obj, spacing: float, thickness: float, where: str = "objects") -> MeshField:
    """The distance grid of a `type = "mesh"` object for a sheet of this particle spacing."""
    key = _file_key(obj.path, where)
    return _field(key, float(obj.scale), tuple(float(v) for v in obj.rotation), float(spacing),
                  float(thickness), where)


def _file_key(path: str, where: str) -> tuple[str, int, int]:
    try:
        p = user_path(path)
    except PathProblem as e:
        raise SceneError(f"{where}.path = {short_repr(path)}: {e}") from None
    if p.suffix.lower() not in SUFFIXES:
        raise SceneError(f"{where}.path = {path!r}: not a mesh file; expected one of "
                         f"{', '.join(SUFFIXES)}")
    try:
        st = p.stat()
    except OSError as e:
        raise SceneError(f"{where}.path = {path!r}: cannot read: {e.strerror}") from None
    if not p.is_file():
        raise SceneError(f"{where}.path = {path!r}: not a file")
    if st.st_size > MAX_FILE_BYTES:
        raise SceneError(f"{where}.path = {path!r}: {st.st_size / 2**20:.0f} MB; mesh files "
                         f"of at most {MAX_FILE_BYTES // 2**20} MB are read")
    return str(p.resolve()), st.st_size, st.st_mtime_ns


@functools.lru_cache(maxsize=8)
def _read_surface(path: str, size: int, mtime: int, where: str):
    """The file's closed triangle surface (a PyVista PolyData). size and mtime are part of
    the cache key: an edited file is read again. The file is parsed and checked by
    mesh_files before VTK is given anything: VTK's readers crash on malformed files."""
    import pyvista as pv

    from .mesh_files import MeshFileError, read_triangles
    try:
        vertices, triangles = read_triangles(path, MAX_TRIANGLES)
    except MeshFileError as e:
        raise SceneError(f"{where}.path = {path!r}: {e}") from None
    except OSError as e:
        raise SceneError(f"{where}.path = {path!r}: cannot read: {e.strerror}") from None
    except MemoryError:
        raise SceneError(f"{where}.path = {path!r}: too large to read into memory") from None
    data = pv.PolyData(vertices, np.c_[np.full(len(triangles), 3), triangles].ravel())
    surface = data.clean()
    if surface.n_points == 0 or surface.n_cells == 0 or surface.area <= 0.0:
        raise SceneError(f"{where}.path = {path!r}: no triangles (an empty or unreadable "
                         "mesh file)")
    bad_edges = surface.extract_feature_edges(boundary_edges=True, non_manifold_edges=True,
                                              feature_edges=False, manifold_edges=False)
    if bad_edges.n_cells:
        raise SceneError(f"{where}.path = {path!r}: the surface is not closed ("
                         f"{bad_edges.n_cells} boundary or non-manifold edges); a mesh "
                         "collider needs a closed surface (fill its holes first)")
    return surface


def _inside(grid, surface) -> np.ndarray:
    """Which grid points a closed surface encloses (vtkSelectEnclosedPoints)."""
    from vtkmodules.vtkFiltersModeling import vtkSelectEnclosedPoints
    select = vtkSelectEnclosedPoints()
    select.SetInputData(grid)
    select.SetSurfaceData(surface)
    select.SetTolerance(1e-6)
    select.Update()
    import pyvista as pv
    return np.asarray(pv.wrap(select.GetOutput())["SelectedPoints"]).astype(bool)


@functools.lru_cache(maxsize=16)  # a grid is up to ~70³ samples × 4 arrays: ≤ 11 MB
def _field(key: tuple, scale: float, rotation: tuple, spacing: float, thickness: float,
           where: str) -> MeshField:
    import pyvista as pv
    raw = _read_surface(*key, where)
    if progress is not None:
        progress(f"building the distance grid of {where} ({raw.n_cells} triangles)")
    surface = raw.copy()
    surface.points = (np.asarray(raw.points, dtype=np.float64) * scale) @ \
        rotation_matrix(rotation).T
    lo, hi = np.asarray(surface.bounds, dtype=np.float64).reshape(3, 2).T
    # the skin counts too: a tiny mesh in a thick skin took 450³ samples (minutes, GBs)
    extent = float((hi - lo).max()) + 2.0 * thickness
    cell = max(spacing / 2.0, extent / MAX_CELLS, 1e-6)
    pad = thickness + PAD_CELLS * cell
    origin = lo - pad
    dims = np.ceil((hi + pad - origin) / cell).astype(int) + 1
    grid = pv.ImageData(dimensions=tuple(int(d) for d in dims), spacing=(cell, cell, cell),
                        origin=tuple(origin))
    d = np.abs(np.asarray(grid.compute_implicit_distance(surface)["implicit_distance"],
                          dtype=np.float64))
    # vtkImplicitPolyDataDistance's own sign comes from the nearest face's normal and is
    # wrong near edges and vertices (measured: ±0.15 m errors on a torus); an inside test by
    # ray casting is not
    d = np.where(_inside(grid, surface), -d, d)
    d = d.reshape(tuple(dims), order="F")  # VTK: x varies fastest
    gradient = np.stack(np.gradient(d, cell), axis=-1)
    faces = np.asarray(surface.regular_faces, dtype=np.int64)
    mesh = MeshSurface(f"{key[0]}|{scale!r}|{rotation!r}",
                       np.ascontiguousarray(surface.points, dtype=np.float64), faces)
    for arr in (mesh.vertices, mesh.faces, d, gradient):
        arr.setflags(write=False)
    return MeshField(mesh, origin, cell, np.ascontiguousarray(d),
                     np.ascontiguousarray(gradient))
