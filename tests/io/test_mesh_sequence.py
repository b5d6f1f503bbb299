"""`cloth-tui bake … -o f_####.obj|.ply`: one mesh per frame that PyVista reads back."""

from pathlib import Path

import numpy as np
import pytest

from cloth_tui.cli import main
from cloth_tui.io.mesh_sequence import sequence_path

from .helpers import simulated_frames


@pytest.mark.parametrize("pattern,frame,name", [
    ("f_####.obj", 7, "f_0007.obj"), ("f_##.ply", 123, "f_123.ply"),
    ("f.obj", 3, "f_0003.obj"), ("a#b_######.obj", 5, "a#b_000005.obj")])
def test_sequence_names(pattern, frame, name):
    assert sequence_path(Path("d") / pattern, frame) == Path("d") / name


@pytest.mark.parametrize("suffix", [".obj", ".ply"])
def test_ten_frames_read_back_as_the_simulation(tmp_path, suffix):
    import pyvista as pv

    assert main(["bake", "sphere", "-o", str(tmp_path / f"f_####{suffix}"), "--frames", "10",
                 "--set", "cloth.resolution=8"]) == 0
    files = sorted(tmp_path.iterdir())
    assert [f.name for f in files] == [f"f_{k:04d}{suffix}" for k in range(1, 11)]
    xs, _ = simulated_frames("sphere", ["cloth.resolution=8"], 10)
    for path, x in zip(files, xs):
        mesh = pv.read(path)
        assert mesh.n_cells == 2 * 7 ** 2
        np.testing.assert_allclose(np.asarray(mesh.points), x, atol=1e-6)
    assert not np.allclose(xs[0], xs[-1])


@pytest.mark.parametrize("suffix", [".obj", ".ply"])
def test_a_rectangle_bakes_with_its_faces_and_proportional_uvs(tmp_path, suffix):
    import pyvista as pv

    sets = ["cloth.size=[2, 0.5]", "cloth.resolution=[17, 5]"]
    assert main(["bake", "default", "-o", str(tmp_path / f"r_####{suffix}"), "--frames", "2",
                 *[a for s in sets for a in ("--set", s)]]) == 0
    xs, _ = simulated_frames("default", sets, 2)
    mesh = pv.read(tmp_path / f"r_0002{suffix}")
    assert mesh.n_cells == 2 * 16 * 4
    np.testing.assert_allclose(np.asarray(mesh.points), xs[-1], atol=1e-6)
    uv = np.asarray(mesh.active_texture_coordinates).reshape(5, 17, 2)
    np.testing.assert_allclose(uv[0, [0, -1], 0], [0.0, 1.0], atol=1e-6)
    np.testing.assert_allclose(uv[[0, -1], 0, 1], [0.625, 0.375], atol=1e-6)  # a quarter


def _whole_frames(folder, suffix, cells):
    import pyvista as pv

    names = sorted(p.name for p in folder.iterdir())
    assert not [n for n in names if n.startswith(".")], names  # no temporary file left
    for name in names:
        mesh = pv.read(folder / name)  # every file under a final name is whole
        assert mesh.n_cells == cells, name
    return names


@pytest.mark.parametrize("suffix", [".obj", ".ply"])
def test_a_full_disk_fails_the_bake_in_one_line_and_keeps_whole_frames(tmp_path, capfd,
                                                                       suffix):
    from tests.small_disk import small_tmpfs

    with small_tmpfs(tmp_path / "small", "200k") as disk:
        rc = main(["bake", "sphere", "-o", str(disk / f"f_####{suffix}"), "--frames", "100",
                   "--set", "cloth.resolution=20"])
        err = capfd.readouterr().err
        assert rc == 2 and err.count("\n") == 1, err
        assert "No space left on device" in err and "before it are whole" in err, err
        names = _whole_frames(disk, suffix, 2 * 19 ** 2)
        assert 1 <= len(names) < 100
        assert names == [f"f_{k:04d}{suffix}" for k in range(1, len(names) + 1)]


def test_a_failed_flush_to_disk_fails_the_bake_and_leaves_no_file(tmp_path, capfd,
                                                                  monkeypatch):
    import errno
    import os

    real_fsync, calls = os.fsync, []

    def fsync_fails_on_the_third(fd):
        calls.append(fd)
        if len(calls) == 3:
            raise OSError(errno.EIO, os.strerror(errno.EIO))
        real_fsync(fd)

    monkeypatch.setattr(os, "fsync", fsync_fails_on_the_third)
    rc = main(["bake", "sphere", "-o", str(tmp_path / "f_####.obj"), "--frames", "10",
               "--set", "cloth.resolution=8"])
    err = capfd.readouterr().err
    assert rc == 2 and err.count("\n") == 1 and "Input/output error" in err, err
    assert "f_0003.obj" in err and "the 2 frame files before it are whole" in err
    assert _whole_frames(tmp_path, ".obj", 2 * 7 ** 2) == ["f_0001.obj", "f_0002.obj"]


@pytest.mark.parametrize("name, says", [
    ("#" * 300 + ".obj", "too long"), ("f_" + "#" * 250 + ".ply", "too long"),
    ("#" * 300 + ".usda", "File name too long")])
def test_names_too_long_for_the_folder_exit_2_before_any_work(tmp_path, capfd, name, says):
    rc = main(["bake", "sphere", "-o", str(tmp_path / name), "--frames", "3"])
    err = capfd.readouterr().err
    assert rc == 2 and err.count("\n") == 1 and says in err, err
    assert list(tmp_path.iterdir()) == []


def test_a_frame_file_name_that_is_a_folder_exits_2_before_any_work(tmp_path, capfd):
    (tmp_path / "f_0007.obj").mkdir()
    rc = main(["bake", "sphere", "-o", str(tmp_path / "f_####.obj"), "--frames", "10"])
    err = capfd.readouterr().err
    assert rc == 2 and err.count("\n") == 1 and "f_0007.obj: is a folder" in err, err
    assert [p.name for p in tmp_path.iterdir()] == ["f_0007.obj"]
    # beyond the frames asked for, the folder is in nobody's way
    assert main(["bake", "sphere", "-o", str(tmp_path / "f_####.obj"), "--frames", "6",
                 "--set", "cloth.resolution=8"]) == 0
