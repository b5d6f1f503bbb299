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
