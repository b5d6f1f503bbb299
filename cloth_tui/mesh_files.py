"""Reading mesh files without trusting them: STL, OBJ and PLY parsed here with NumPy, every
count checked against the bytes the file holds and every face index against its vertices,
before any C++ sees the data. (VTK's readers believed a PLY header claiming 10¹¹ vertices, and
a face naming a vertex that does not exist, and died with a segmentation fault.) VTK's own
formats (.vtk, .vtp) are read by VTK in a child process, whose death is reported in one line.

`read_triangles(path)` returns (vertices (V, 3) float64, triangles (F, 3) int64), polygons fanned
into triangles, or raises MeshFileError with a one-line reason.
"""

from __future__ import annotations

import os
import re
import subprocess
import sys
import tempfile

import numpy as np

MAX_VERTICES = 10_000_000   # more than any surface the triangle limit lets through needs
MAX_POLYGON = 1000          # vertices of one face
CHILD_TIMEOUT_S = 120.0     # a VTK reader that takes longer is taken to hang


class MeshFileError(Exception):
    """A mesh file that cannot be used; the message is one line."""


def read_triangles(path: str, max_triangles: int) -> tuple[np.ndarray, np.ndarray]:
    suffix = os.path.splitext(path)[1].lower()
    with open(path, "rb") as fh:
        data = fh.read()
    if suffix == ".stl":
        vertices, triangles = _stl(data, max_triangles)
    elif suffix == ".obj":
        vertices, triangles = _obj(data, max_triangles)
    elif suffix == ".ply":
        vertices, triangles = _ply(data, max_triangles)
    else:
        vertices, triangles = _vtk_in_child(path)
    return _checked(vertices, triangles, max_triangles, base=1 if suffix == ".obj" else 0)


def _checked(vertices, triangles, max_triangles, base: int):
    """`base`: what the file calls its first vertex (OBJ 1, the others 0), for the message."""
    vertices = np.asarray(vertices, dtype=np.float64).reshape(-1, 3)
    triangles = np.asarray(triangles, dtype=np.int64).reshape(-1, 3)
    if len(triangles) == 0:
        raise MeshFileError("no triangles (an empty or unreadable mesh file)")
    if len(triangles) > max_triangles:
        raise MeshFileError(f"{len(triangles)} triangles; at most {max_triangles} are allowed")
    if triangles.min() < 0 or triangles.max() >= len(vertices):
        bad = int(triangles[(triangles < 0) | (triangles >= len(vertices))][0])
        raise MeshFileError(f"a face names vertex {bad + base}, but the file has "
                            f"{len(vertices)} vertices (from {base})")
    if not np.all(np.isfinite(vertices)):
        raise MeshFileError("the mesh has non-finite coordinates")
    return np.ascontiguousarray(vertices), np.ascontiguousarray(triangles)


def _fan(polygons) -> np.ndarray:
    """Triangles (a, b, c), (a, c, d), … of each polygon (lists of vertex indices)."""
    out = []
    for p in polygons:
        if len(p) < 3:
            raise MeshFileError(f"a face with {len(p)} vertices (a face needs at least 3)")
        if len(p) > MAX_POLYGON:
            raise MeshFileError(f"a face with {len(p)} vertices; at most {MAX_POLYGON}")
        out.extend((p[0], p[k], p[k + 1]) for k in range(1, len(p) - 1))
    try:
        return np.array(out, dtype=np.int64).reshape(-1, 3)
    except OverflowError:  # an ASCII PLY index past int64: its reader keeps Python ints
        big = next(i for t in out for i in t if abs(int(i)) > MAX_VERTICES)
        raise MeshFileError(f"a face names vertex {big}; a file has at most {MAX_VERTICES} "
                            "vertices") from None


# -- STL --------------------------------------------------------------------------------
_STL_VERTEX = re.compile(rb"vertex\s+(\S+)\s+(\S+)\s+(\S+)")


def _stl(data: bytes, max_triangles: int):
    if len(data) >= 84:
        count = int.from_bytes(data[80:84], "little")
        if len(data) == 84 + 50 * count:  # binary: its size says so exactly
            if count > max_triangles:
                raise MeshFileError(f"{count} triangles; at most {max_triangles} are allowed")
            rec = np.frombuffer(data, dtype=np.dtype([("n", "<f4", 3), ("v", "<f4", (3, 3)),
                                                      ("a", "<u2")]), count=count, offset=84)
            points = rec["v"].reshape(-1, 3).astype(np.float64)
            return points, np.arange(len(points), dtype=np.int64).reshape(-1, 3)
    if not data.lstrip().startswith(b"solid"):
        raise MeshFileError("not an STL file (neither a binary STL, whose size is 84 + 50 "
                            "bytes per triangle, nor text starting with 'solid')")
    try:
        points = np.array(_STL_VERTEX.findall(data), dtype=np.float64)
    except ValueError:
        raise MeshFileError("a vertex of the STL file is not three numbers") from None
    if len(points) % 3:
        raise MeshFileError(f"{len(points)} vertices in the STL file, not 3 per triangle")
    return points.reshape(-1, 3), np.arange(len(points), dtype=np.int64).reshape(-1, 3)


# -- OBJ --------------------------------------------------------------------------------
def _obj(data: bytes, max_triangles: int):
    vertices, polygons = [], []
    for number, line in enumerate(data.splitlines(), 1):
        parts = line.split()
        if not parts:
            continue
        try:
            if parts[0] == b"v":
                if len(parts) < 4:
                    raise ValueError
                vertices.append((float(parts[1]), float(parts[2]), float(parts[3])))
                if len(vertices) > MAX_VERTICES:
                    raise MeshFileError(f"more than {MAX_VERTICES} vertices")
            elif parts[0] == b"f":
                count = len(vertices)
                face = []
                for token in parts[1:]:
                    k = int(token.split(b"/", 1)[0])
                    if abs(k) > MAX_VERTICES:
                        raise MeshFileError(f"line {number}: vertex index {k}; a file has at "
                                            f"most {MAX_VERTICES} vertices")
                    if k == 0:
                        raise MeshFileError(f"line {number}: vertex index 0 (OBJ counts "
                                            "from 1)")
                    # 1-based; a negative index counts back from the last vertex so far
                    face.append(k - 1 if k > 0 else count + k)
                polygons.append(face)
                if len(polygons) > max_triangles:
                    raise MeshFileError(f"more than {max_triangles} faces; at most "
                                        f"{max_triangles} triangles are allowed")
        except ValueError:
            kind = parts[0][:10].decode("ascii", "replace")
            raise MeshFileError(f"line {number}: not a valid {kind!r} line") from None
    return np.array(vertices, dtype=np.float64).reshape(-1, 3), _fan(polygons)


# -- PLY --------------------------------------------------------------------------------
_PLY_TYPES = {"char": "i1", "int8": "i1", "uchar": "u1", "uint8": "u1", "short": "i2",
              "int16": "i2", "ushort": "u2", "uint16": "u2", "int": "i4", "int32": "i4",
              "uint": "u4", "uint32": "u4", "float": "f4", "float32": "f4", "double": "f8",
              "float64": "f8"}
_PLY_FORMATS = {"ascii": None, "binary_little_endian": "<", "binary_big_endian": ">"}


def _ply_type(name: str) -> str:
    if name not in _PLY_TYPES:
        raise MeshFileError(f"PLY header: unknown property type {name[:20]!r}")
    return _PLY_TYPES[name]


def _ply_header(data: bytes):
    end = data.find(b"end_header")
    if not data.startswith(b"ply") or end < 0:
        raise MeshFileError("not a PLY file (no 'ply' ... 'end_header' header)")
    body = end + len(b"end_header")
    body += 2 if data[body:body + 2] == b"\r\n" else 1
    fmt, elements = None, []
    for line in data[:end].decode("ascii", "replace").splitlines()[1:]:
        words = line.split()
        if not words or words[0] in ("comment", "obj_info"):
            continue
        if words[0] == "format" and len(words) >= 2 and words[1] in _PLY_FORMATS:
            fmt = words[1]
        elif words[0] == "element" and len(words) == 3 and words[2].isdigit():
            elements.append((words[1], int(words[2]), []))
        elif words[0] == "property" and elements and len(words) == 5 and words[1] == "list":
            elements[-1][2].append((words[4], _ply_type(words[3]), _ply_type(words[2])))
        elif words[0] == "property" and elements and len(words) == 3:
            elements[-1][2].append((words[2], _ply_type(words[1]), None))
        else:
            raise MeshFileError(f"PLY header: cannot read the line {line[:40]!r}")
    if fmt is None:
        raise MeshFileError("PLY header: no known format line")
    return fmt, elements, body


def _ply(data: bytes, max_triangles: int):
    fmt, elements, body = _ply_header(data)
    order = _PLY_FORMATS[fmt]
    left = len(data) - body
    for name, count, props in elements:  # the counts must fit the file: check before reading
        least = sum(np.dtype(t if c is None else c).itemsize for _, t, c in props) \
            if order else 2 * max(1, len(props))  # ascii: a digit and a space per value
        if count * least > left:
            raise MeshFileError(f"the PLY header claims {count} {name} elements, more than "
                                f"the file's {left} bytes after its header can hold")
    if fmt == "ascii":
        reader = _AsciiBody(data[body:])
    else:
        reader = _BinaryBody(data, body, order)
    vertices = polygons = None
    for name, count, props in elements:
        if name == "vertex":
            if count > MAX_VERTICES:
                raise MeshFileError(f"{count} vertices; at most {MAX_VERTICES}")
            columns = reader.element(count, props)
            try:
                vertices = np.stack([columns[a] for a in "xyz"], axis=1).astype(np.float64)
            except KeyError:
                raise MeshFileError("PLY vertices without x, y and z") from None
        elif name == "face":
            if count > max_triangles:
                raise MeshFileError(f"{count} faces; at most {max_triangles} triangles are "
                                    "allowed")
            columns = reader.element(count, props)
            lists = columns.get("vertex_indices", columns.get("vertex_index"))
            if lists is None:
                raise MeshFileError("PLY faces without a vertex_indices list")
            polygons = lists
        else:
            reader.element(count, props)
    if vertices is None or polygons is None:
        raise MeshFileError("no triangles (a PLY file needs vertex and face elements)")
    if isinstance(polygons, np.ndarray):  # every face had the same size: no loop needed
        if polygons.shape[1] < 3:
            raise MeshFileError(f"a face with {polygons.shape[1]} vertices (a face needs at "
                                "least 3)")
        k = polygons.shape[1]
        fan = np.stack([polygons[:, [0, j, j + 1]] for j in range(1, k - 1)], axis=1)
        return vertices, fan.reshape(-1, 3)
    return vertices, _fan(polygons)


class _BinaryBody:
    def __init__(self, data: bytes, offset: int, order: str):
        self.data, self.offset, self.order = data, offset, order

    def _take(self, dtype, count: int) -> np.ndarray:
        dtype = np.dtype(dtype).newbyteorder(self.order)
        end = self.offset + dtype.itemsize * count
        if end > len(self.data):
            raise MeshFileError("the PLY file ends before its header's elements do")
        out = np.frombuffer(self.data, dtype=dtype, count=count, offset=self.offset)
        self.offset = end
        return out

    def element(self, count: int, props) -> dict:
        if all(c is None for _, _, c in props):
            rec = self._take(np.dtype([(n, t) for n, t, _ in props]), count)
            return {n: rec[n] for n, _, _ in props}
        if len(props) == 1 and count:  # one list (a face's indices): try one size for all
            name, item, counted = props[0]
            first = int(self._peek(counted))
            if 0 <= first <= MAX_POLYGON:
                dtype = np.dtype([("n", counted), ("i", item, (first,))]).newbyteorder(
                    self.order)
                if self.offset + dtype.itemsize * count <= len(self.data):
                    rec = np.frombuffer(self.data, dtype=dtype, count=count, offset=self.offset)
                    if np.all(rec["n"] == first):
                        self.offset += dtype.itemsize * count
                        return {name: _indices(rec["i"])}
        out = {n: [] for n, _, _ in props}
        for _ in range(count):
            for name, item, counted in props:
                if counted is None:
                    out[name].append(self._take(item, 1)[0])
                else:
                    n = int(self._take(counted, 1)[0])
                    if not 0 <= n <= MAX_POLYGON:
                        raise MeshFileError(f"a PLY list of {n} items; at most {MAX_POLYGON}")
                    out[name].append(_indices(self._take(item, n)).tolist())
        return out

    def _peek(self, dtype):
        dtype = np.dtype(dtype).newbyteorder(self.order)
        if self.offset + dtype.itemsize > len(self.data):
            raise MeshFileError("the PLY file ends before its header's elements do")
        return np.frombuffer(self.data, dtype=dtype, count=1, offset=self.offset)[0]


def _indices(values: np.ndarray) -> np.ndarray:
    if values.dtype.kind == "f":
        if not np.all(np.isfinite(values)) or np.any(values != np.round(values)):
            raise MeshFileError("a PLY face index that is not a whole number")
    return values.astype(np.int64)


class _AsciiBody:
    def __init__(self, text: bytes):
        self.tokens = text.split()
        self.at = 0

    def _take(self, count: int) -> list:
        if self.at + count > len(self.tokens):
            raise MeshFileError("the PLY file ends before its header's elements do")
        out = self.tokens[self.at:self.at + count]
        self.at += count
        return out

    def element(self, count: int, props) -> dict:
        try:
            if all(c is None for _, _, c in props):
                values = np.array(self._take(count * len(props)), dtype=np.float64)
                values = values.reshape(count, len(props))
                return {n: values[:, j] for j, (n, _, _) in enumerate(props)}
            out = {n: [] for n, _, _ in props}
            for _ in range(count):
                for name, _, counted in props:
                    if counted is None:
                        out[name].append(float(self._take(1)[0]))
                        continue
                    n = int(self._take(1)[0])
                    if not 0 <= n <= MAX_POLYGON:
                        raise MeshFileError(f"a PLY list of {n} items; at most {MAX_POLYGON}")
                    out[name].append([int(t) for t in self._take(n)])
            return out
        except ValueError:
            raise MeshFileError("a PLY value that is not a number (or an index that is not "
                                "a whole number)") from None


# -- VTK's formats, in a child process ----------------------------------------------------
_CHILD = r"""
import sys, warnings
import numpy as np
from vtkmodules.vtkCommonCore import vtkObject
vtkObject.GlobalWarningDisplayOff()
import pyvista as pv
with warnings.catch_warnings():
    warnings.simplefilter("ignore")
    data = pv.read(sys.argv[1])
    if not isinstance(data, pv.PolyData):
        data = data.extract_surface()
    data = data.triangulate() if data.n_cells else data
    try:  # after triangulate() every polygon is a triangle: (3, a, b, c) rows
        faces = np.asarray(data.faces).reshape(-1, 4)[:, 1:]
    except ValueError:
        faces = np.zeros((0, 3))
np.savez(sys.argv[2], points=np.asarray(data.points, dtype=np.float64).reshape(-1, 3),
         faces=np.asarray(faces, dtype=np.int64).reshape(-1, 3))
"""


def _vtk_in_child(path: str):
    """VTK reads its own formats in a child process: a reader that crashes on a malformed
    file takes only the child with it, and its error lines go nowhere."""
    with tempfile.TemporaryDirectory(prefix="cloth-tui-mesh-") as folder:
        out = os.path.join(folder, "mesh.npz")
        try:
            child = subprocess.run([sys.executable, "-c", _CHILD, path, out],
                                   stdin=subprocess.DEVNULL, stdout=subprocess.DEVNULL,
                                   stderr=subprocess.PIPE, timeout=CHILD_TIMEOUT_S)
        except subprocess.TimeoutExpired:
            raise MeshFileError(f"VTK's reader did not finish in {CHILD_TIMEOUT_S:.0f} s") \
                from None
        if child.returncode < 0:
            raise MeshFileError(f"VTK's reader crashed on it (signal {-child.returncode}): "
                                "a malformed file")
        if child.returncode != 0 or not os.path.exists(out):
            lines = [ln for ln in child.stderr.decode("utf-8", "replace").splitlines()
                     if ln.strip()]
            last = lines[-1].strip()[:200] if lines else f"exit status {child.returncode}"
            raise MeshFileError(f"VTK's reader failed: {last}")
        with np.load(out) as arrays:
            return arrays["points"], arrays["faces"]
