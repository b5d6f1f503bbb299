"""A torn sheet's bake shows the tear as the renderer draws it: faces across a torn constraint
are left out (USD: time-sampled faces; OBJ/PLY: each frame's own), and a USD bake keeps the
intact flags, so a replay draws the same gaps."""

import numpy as np
import pytest

from cloth_tui.cli import main
from cloth_tui.io.frames import BakedFrame, SheetFaces
from cloth_tui.scene_files import load
from cloth_tui.sim.run.runner import Simulation
from cloth_tui.sim.effects.tearing import intact_triangles

FRAMES = 50  # the built-in `tear` scene starts tearing at about frame 40


@pytest.fixture(scope="module")
def torn_run():
    """(model, intact flags per frame from frame 1) of the run the bakes make."""
    sim = Simulation(load("tear"))
    alive = []
    for _ in range(FRAMES):
        sim.advance_frame()
        alive.append(sim.state.alive.copy())
    assert alive[0].all() and not alive[-1].all()  # intact at first, torn by the end
    return sim.model, alive


def test_sheet_faces_follow_the_tears(torn_run):
    model, alive = torn_run
    faces = SheetFaces(model)
    assert not faces.update(None) and faces.triangles is faces.all
    assert faces.update(alive[-1])
    np.testing.assert_array_equal(faces.triangles, intact_triangles(model, alive[-1]))
    assert not faces.update(alive[-1].copy())  # the same tear: nothing to write again
    assert faces.update(np.ones_like(alive[-1])) and faces.triangles is faces.all  # healed


def test_usd_bake_samples_the_faces_where_they_change_and_keeps_the_flags(tmp_path, torn_run):
    pytest.importorskip("pxr")
    from pxr import Usd, UsdGeom

    from cloth_tui.io.bake_player import BakePlayer
    from cloth_tui.io.usd_read import UsdBake

    model, alive = torn_run
    out = tmp_path / "t.usdc"
    assert main(["bake", "tear", "-o", str(out), "--frames", str(FRAMES)]) == 0
    stage = Usd.Stage.Open(str(out))  # kept: the prims live as long as their stage
    cloth = UsdGeom.Mesh.Get(stage, "/World/Cloth")
    indices, flags = cloth.GetFaceVertexIndicesAttr(), cloth.GetPrim().GetAttribute(
        "cloth_tui:alive")
    samples = indices.GetTimeSamples()
    assert samples[0] == 1.0 and len(samples) > 1  # the whole sheet, then each change
    for k in range(1, FRAMES + 1):
        want = intact_triangles(model, alive[k - 1])
        got = np.asarray(indices.Get(float(k))).reshape(-1, 3)
        np.testing.assert_array_equal(got, want)
        assert len(cloth.GetFaceVertexCountsAttr().Get(float(k))) == len(want)
        np.testing.assert_array_equal(np.asarray(flags.Get(float(k))), alive[k - 1])

    bake = UsdBake(out)
    assert bake.alive(1) is None
    np.testing.assert_array_equal(bake.alive(FRAMES), alive[-1])
    player = BakePlayer(bake, bake.scene)
    player.seek(player.count - 1, now=0.0)
    np.testing.assert_array_equal(player.snapshot().alive, alive[-1])


def test_a_bake_begun_on_a_torn_sheet_has_no_whole_sheet_sample(tmp_path, torn_run):
    # The app's `e` on a sheet already cut: its first frame's faces are the torn ones.
    pytest.importorskip("pxr")
    from pxr import Usd, UsdGeom

    from cloth_tui.io.usd_bake import UsdBakeWriter

    model, alive = torn_run
    writer = UsdBakeWriter(tmp_path / "cut.usda", load("tear"), model)
    for k in (1, 2):
        writer.write(BakedFrame(k, k / 60, model.rest_positions, (), alive[-1]))
    writer.close()
    stage = Usd.Stage.Open(str(tmp_path / "cut.usda"))
    cloth = UsdGeom.Mesh.Get(stage, "/World/Cloth")
    indices = cloth.GetFaceVertexIndicesAttr()
    assert indices.GetTimeSamples() == [1.0]
    np.testing.assert_array_equal(np.asarray(indices.Get(1.0)).reshape(-1, 3),
                                  intact_triangles(model, alive[-1]))


def test_a_bake_whose_flags_do_not_fit_its_scene_is_refused(tmp_path, torn_run):
    pytest.importorskip("pxr")
    from pxr import Sdf, Usd, UsdGeom, Vt

    from cloth_tui.io.bake_player import bake_model
    from cloth_tui.io.usd_read import UsdBake
    from cloth_tui.usage import UsageError

    out = tmp_path / "t.usda"
    assert main(["bake", "tear", "-o", str(out), "--frames", "2"]) == 0
    stage = Usd.Stage.Open(str(out))
    prim = UsdGeom.Mesh.Get(stage, "/World/Cloth").GetPrim()
    prim.CreateAttribute("cloth_tui:alive", Sdf.ValueTypeNames.UCharArray, custom=True).Set(
        Vt.UCharArray.FromNumpy(np.zeros(7, np.uint8)), 2.0)
    stage.GetRootLayer().Save()
    bake = UsdBake(out)
    with pytest.raises(UsageError, match="7 constraint flags"):
        bake_model(bake, bake.scene)


@pytest.mark.parametrize("suffix", [".obj", ".ply"])
def test_mesh_sequence_frames_leave_out_the_torn_faces(tmp_path, torn_run, suffix):
    import pyvista as pv

    model, alive = torn_run
    assert main(["bake", "tear", "-o", str(tmp_path / f"f_####{suffix}"), "--frames",
                 str(FRAMES)]) == 0
    first, last = pv.read(tmp_path / f"f_0001{suffix}"), pv.read(
        tmp_path / f"f_{FRAMES:04d}{suffix}")
    assert first.n_cells == len(model.triangles)
    want = intact_triangles(model, alive[-1])
    assert last.n_cells == len(want) < len(model.triangles)
    np.testing.assert_array_equal(np.asarray(last.faces).reshape(-1, 4)[:, 1:], want)
