"""Mesh files for `type = "mesh"` objects: bad ones exit 2 with one line naming the problem;
paths are relative to the scene file."""

import json

import numpy as np
import pytest

pv = pytest.importorskip("pyvista")

from cloth_tui import meshes  # noqa: E402
from cloth_tui.cli import main  # noqa: E402
from cloth_tui.scene import SceneError, SceneObject  # noqa: E402
from cloth_tui.scene_files import loads  # noqa: E402


def write_scene(folder, mesh_path: str):
    path = folder / "scene.toml"
    path.write_text(f'[[objects]]\ntype = "mesh"\npath = "{mesh_path}"\ncenter = [0.0, -0.3, '
                    f'0.0]\n', encoding="utf-8")
    return path


def simulate(capfd, scene_path, *extra):
    rc = main(["simulate", str(scene_path), "--frames", "2", "--json", *extra])
    out, err = capfd.readouterr()
    return rc, out, err


@pytest.fixture(scope="module")
def torus(tmp_path_factory):
    path = tmp_path_factory.mktemp("m") / "torus.stl"
    pv.ParametricTorus(ringradius=0.25, crosssectionradius=0.08).triangulate().save(path)
    return path


def make_bad(folder, kind):
    if kind == "missing":
        return folder / "missing.stl"
    if kind == "garbage":
        (folder / "garbage.stl").write_bytes(b"\x00\x01garbage" * 10)
        return folder / "garbage.stl"
    if kind == "empty":
        (folder / "empty.obj").write_text("")
        return folder / "empty.obj"
    if kind == "broken_ply":
        (folder / "b.ply").write_text("ply\nformat ascii 1.0\nelement vertex 3\nend_header\n1 2\n")
        return folder / "b.ply"
    if kind == "not_a_mesh":
        (folder / "notes.txt").write_text("hi")
        return folder / "notes.txt"
    if kind == "open":
        pv.Plane().triangulate().save(folder / "open.stl")
        return folder / "open.stl"
    if kind == "points_only":
        pv.PolyData(np.array([[0.0, 0, 0], [1, 0, 0]])).save(folder / "points.vtk")
        return folder / "points.vtk"
    raise AssertionError(kind)


@pytest.mark.parametrize("kind, says", [
    ("missing", "No such file"), ("garbage", "not an STL file"), ("empty", "no triangles"),
    ("broken_ply", "claims 3 vertex"), ("not_a_mesh", "not a mesh file"),
    ("open", "not closed"), ("points_only", "no triangles")])
def test_bad_mesh_files_exit_2_with_one_line(tmp_path, capfd, kind, says):
    scene = write_scene(tmp_path, make_bad(tmp_path, kind).name)
    rc, out, err = simulate(capfd, scene)
    assert rc == 2 and out == ""
    assert err.count("\n") == 1 and "objects[0].path" in err and says in err, err


def test_huge_meshes_exit_2_with_one_line(tmp_path, capfd, torus, monkeypatch):
    scene = write_scene(tmp_path, str(torus))
    meshes._read_surface.cache_clear()  # the limit is checked when the file is read
    monkeypatch.setattr(meshes, "MAX_TRIANGLES", 100)
    rc, _, err = simulate(capfd, scene)
    assert rc == 2 and err.count("\n") == 1 and "triangles; at most 100" in err
    monkeypatch.setattr(meshes, "MAX_FILE_BYTES", 1000)
    rc, _, err = simulate(capfd, scene)
    assert rc == 2 and err.count("\n") == 1 and "MB are read" in err


def test_the_path_is_relative_to_the_scene_file(tmp_path, capfd, torus, monkeypatch):
    (tmp_path / "meshes").mkdir()
    (tmp_path / "meshes" / "t.stl").write_bytes(torus.read_bytes())
    (tmp_path / "scenes").mkdir()
    scene = write_scene(tmp_path / "scenes", "../meshes/t.stl")
    monkeypatch.chdir(tmp_path / "meshes")  # not where the scene is
    rc, out, err = simulate(capfd, scene)
    assert rc == 0, err
    assert "collide_mesh" in json.loads(out)["effects"]


def test_mesh_objects_need_a_path_and_only_they_take_one():
    with pytest.raises(SceneError, match=r"objects\[0\]: a mesh needs `path`"):
        loads('[[objects]]\ntype = "mesh"\n')
    with pytest.raises(SceneError, match="`path` is for meshes, not a sphere"):
        loads('[[objects]]\ntype = "sphere"\npath = "a.stl"\n')
    with pytest.raises(SceneError, match="scene.object"):
        loads('[scene]\nobject = "mesh"\n')  # the original's single object has no file


def test_rotation_is_about_x_then_y_then_z():
    r = meshes.rotation_matrix([90.0, 90.0, 0.0])
    # x first takes +y to +z, then y takes +z to +x
    assert r @ np.array([0.0, 1.0, 0.0]) == pytest.approx([1.0, 0.0, 0.0], abs=1e-12)
    assert SceneObject().rotation == [0.0, 0.0, 0.0] and SceneObject().scale == 1.0


@pytest.fixture(scope="module")
def coarse_torus(tmp_path_factory):
    """A torus of 506 triangles: the grid's size does not depend on how finely the surface is
    cut, and its distances cost time in proportion to the triangles."""
    path = tmp_path_factory.mktemp("m") / "coarse_torus.stl"
    pv.ParametricTorus(ringradius=0.25, crosssectionradius=0.08, u_res=24,
                       v_res=12).triangulate().clean().save(path)
    return path


@pytest.mark.parametrize("scale,thickness", [(1e-12, 0.12), (1e-3, 0.3), (1.0, 1.0), (1.0, 0.0)])
def test_the_distance_grid_stays_bounded_whatever_the_skin(coarse_torus, scale, thickness):
    # a tiny mesh in a thick skin under a fine sheet (spacing 4.4 mm, issue 19's fuzzer) was
    # sampled on a grid of skin / (spacing / 2) cells a side: 450³ at thickness 0.5 m
    field = meshes.field_for(SceneObject(type="mesh", path=str(coarse_torus), scale=scale),
                             spacing=1.0 / 226, thickness=thickness)
    assert max(field.distance.shape) <= meshes.MAX_CELLS + 2 * meshes.PAD_CELLS + 2
    assert field.cell * (max(field.distance.shape) - 1) >= 2 * thickness  # the skin is inside


@pytest.mark.parametrize("mesh_path, says", [("a\\u0000b.stl", "a NUL byte in the file name"),
                                             ("~nosuchuser/m.stl", "no such user's home")])
def test_mesh_paths_no_file_system_takes_exit_2_with_one_line(tmp_path, capfd, mesh_path, says):
    rc, out, err = simulate(capfd, write_scene(tmp_path, mesh_path))
    assert rc == 2 and out == ""
    assert err.count("\n") == 1 and "objects[0].path" in err and says in err, err


def test_a_scene_whose_meshes_hold_too_many_triangles_is_refused_before_any_grid(tmp_path,
                                                                                 capfd):
    big = tmp_path / "big.stl"
    pv.Icosphere(nsub=7).save(big)  # 327,680 triangles, as in the slow scene found
    objects = "".join(f'[[objects]]\ntype = "mesh"\npath = "big.stl"\nscale = 0.1\n'
                      f'center = [{0.3 * k - 1.0}, -0.5, 0.0]\n' for k in range(7))
    scene = tmp_path / "many.toml"
    scene.write_text(objects, encoding="utf-8")
    rc, out, err = simulate(capfd, scene)
    assert rc == 2 and out == "" and err.count("\n") == 1, err
    assert f"at most {meshes.MAX_SCENE_TRIANGLES} in all" in err and "objects[6]" in err


def test_each_grid_built_is_announced_on_a_terminal(tmp_path, capsys, torus):
    from cloth_tui.interrupt import mesh_grid_progress
    from cloth_tui.sim.collision.colliders import build_colliders
    from cloth_tui.sim.model import build_model

    scene = loads(f'[[objects]]\ntype = "mesh"\npath = "{torus}"\nscale = 0.7\n'
                  f'center = [0.0, -0.3, 0.0]\n')
    meshes._field.cache_clear()
    with mesh_grid_progress(True):
        build_colliders(scene, build_model(scene.cloth, scene.behavior))
    err = capsys.readouterr().err
    assert "building the distance grid of objects[0]" in err and "triangles" in err
    assert err.endswith("\r\x1b[K")  # the line is cleared for what follows
    with mesh_grid_progress(False):
        meshes._field.cache_clear()
        build_colliders(scene, build_model(scene.cloth, scene.behavior))
    assert capsys.readouterr().err == ""
