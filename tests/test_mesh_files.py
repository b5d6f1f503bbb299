"""Mesh files are parsed and checked before VTK sees them: hostile counts and indices get one
line and exit 2 (VTK's readers died of a segmentation fault on them), good files read as VTK
reads them."""

import subprocess
import sys

import numpy as np
import pytest

from cloth_tui.mesh_files import MeshFileError, read_triangles

PLY_HEAD = ("ply\nformat {fmt} 1.0\nelement vertex {nv}\nproperty float x\nproperty float y\n"
            "property float z\nelement face {nf}\nproperty list uchar int vertex_indices\n"
            "end_header\n")
TETRA = np.array([[0, 0, 0], [1, 0, 0], [0, 1, 0], [0, 0, 1]], dtype=np.float32)
TETRA_FACES = np.array([[0, 2, 1], [0, 1, 3], [0, 3, 2], [1, 2, 3]])


def binary_ply(nv, nf, faces=TETRA_FACES, body_bytes=None) -> bytes:
    head = PLY_HEAD.format(fmt="binary_little_endian", nv=nv, nf=nf).encode()
    body = TETRA.tobytes() + b"".join(bytes([3]) + np.asarray(f, "<i4").tobytes()
                                      for f in faces)
    return head + (body if body_bytes is None else body[:body_bytes])


def ascii_ply(nv, nf, faces=TETRA_FACES) -> bytes:
    head = PLY_HEAD.format(fmt="ascii", nv=nv, nf=nf)
    return (head + "".join(f"{x} {y} {z}\n" for x, y, z in TETRA)
            + "".join(f"3 {a} {b} {c}\n" for a, b, c in faces)).encode()


def obj(faces) -> bytes:
    return ("".join(f"v {x} {y} {z}\n" for x, y, z in TETRA)
            + "".join("f " + " ".join(map(str, f)) + "\n" for f in faces)).encode()


HOSTILE = {
    "ply claims 1e11 vertices": ("a.ply", ascii_ply(10**11, 4), "claims 100000000000 vertex"),
    "binary ply claims 2e9 vertices, 100-byte body":
        ("b.ply", binary_ply(2 * 10**9, 4, body_bytes=100), "claims 2000000000 vertex"),
    "ply face index beyond the vertices":
        ("c.ply", binary_ply(4, 4, faces=[[0, 1, 2], [0, 1, 900], [0, 2, 3], [1, 2, 3]]),
         "names vertex 900"),
    "ascii ply negative index": ("d.ply", ascii_ply(4, 4, faces=[[0, 1, -5]] * 4),
                                 "names vertex -5"),
    "ply claims more faces than its body": ("e.ply", binary_ply(4, 10**6), "claims 1000000"),
    "obj face index beyond the vertices": ("f.obj", obj([[1, 3, 2], [1, 2, 900], [1, 4, 3]]),
                                           "names vertex 900"),
    "obj index 0": ("g.obj", obj([[0, 1, 2]]), "index 0"),
    "obj index 10^20": ("i.obj", obj([[1, 2, 10**20]]), "vertex index 100000000000000000000"),
    "stl binary count larger than the file": ("h.stl", b"\0" * 80 + (10**8).to_bytes(4, "little")
                                              + b"\0" * 100, "not an STL file"),
}


@pytest.mark.parametrize("case", sorted(HOSTILE))
def test_hostile_mesh_files_give_one_line_and_exit_2(tmp_path, case):
    name, data, says = HOSTILE[case]
    (tmp_path / name).write_bytes(data)
    scene = tmp_path / "scene.toml"
    scene.write_text(f'[cloth]\nresolution = 8\n[[objects]]\ntype = "mesh"\npath = "{name}"\n'
                     'center = [0.0, -0.3, 0.0]\n', encoding="utf-8")
    # a child process: on a segfault it is the child that dies, and the test that fails
    run = subprocess.run([sys.executable, "-m", "cloth_tui", "simulate", str(scene),
                          "--frames", "1"], capture_output=True, text=True, timeout=120)
    assert run.returncode == 2, (run.returncode, run.stderr)
    assert run.stderr.count("\n") == 1 and says in run.stderr, run.stderr
    assert "\x1b" not in run.stderr  # no VTK error line with its colour escapes


def test_an_ascii_ply_index_past_int64_is_a_mesh_file_error(tmp_path):
    # found by tools/fuzz_files.py (seed 40, case 128): an OverflowError, exit 1
    path = tmp_path / "big.ply"
    path.write_bytes(ascii_ply(4, 4, faces=[[0, 1, 2], [0, 1, 10**20], [0, 2, 3], [1, 2, 3]]))
    with pytest.raises(MeshFileError, match="names vertex 100000000000000000000"):
        read_triangles(path, 1000)


@pytest.mark.parametrize("data", [ascii_ply(4, 4), binary_ply(4, 4),
                                  obj([[1, 3, 2], [1, 2, 4], [1, 4, 3], [2, 3, 4]])],
                         ids=["ascii ply", "binary ply", "obj"])
def test_good_files_give_their_triangles(tmp_path, data):
    path = tmp_path / ("m.obj" if data.startswith(b"v ") else "m.ply")
    path.write_bytes(data)
    vertices, triangles = read_triangles(str(path), 100)
    assert np.array_equal(vertices, TETRA.astype(np.float64))
    assert np.array_equal(triangles, TETRA_FACES)


@pytest.mark.parametrize("suffix, binary", [(".stl", True), (".stl", False), (".ply", True),
                                            (".ply", False), (".obj", False), (".vtk", False),
                                            (".vtp", True)])
def test_files_vtk_writes_read_as_vtk_reads_them(tmp_path, suffix, binary):
    pv = pytest.importorskip("pyvista")
    mesh = pv.Icosphere(nsub=2).triangulate()
    path = tmp_path / f"s{suffix}"
    mesh.save(path, binary=binary) if suffix != ".obj" else mesh.save(path)
    vertices, triangles = read_triangles(str(path), 10_000)
    ours = pv.PolyData(vertices, np.c_[np.full(len(triangles), 3), triangles].ravel()).clean()
    theirs = pv.read(path).clean()
    assert ours.n_cells == theirs.n_cells == mesh.n_cells
    assert ours.area == pytest.approx(theirs.area, rel=1e-6)


def test_polygons_are_fanned_and_mixed_sizes_read(tmp_path):
    path = tmp_path / "q.obj"
    path.write_text("v 0 0 0\nv 1 0 0\nv 1 1 0\nv 0 1 0\nf 1 2 3 4\nf 1/1/1 2/2/2 3/3/3\n"
                    "f -4 -3 -2\n")
    _, triangles = read_triangles(str(path), 10)
    assert triangles.tolist() == [[0, 1, 2], [0, 2, 3], [0, 1, 2], [0, 1, 2]]


def test_a_crashing_vtk_reader_takes_only_its_child(tmp_path, monkeypatch):
    from cloth_tui import mesh_files
    monkeypatch.setattr(mesh_files, "_CHILD", "import os, signal; os.kill(os.getpid(), "
                                              "signal.SIGSEGV)")
    path = tmp_path / "x.vtk"
    path.write_text("# vtk DataFile Version 3.0\n")
    with pytest.raises(MeshFileError, match=r"crashed on it \(signal 11\)"):
        read_triangles(str(path), 10)
