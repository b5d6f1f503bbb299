"""The picture's qualities (issue 14 item 3): the sheet's underside, its shadow, the ground
grid, framing in a tall view, anti-aliasing."""

import numpy as np

from cloth_tui.render.antialias import antialias
from cloth_tui.render.renderer import BACK_SHADE

from .helpers import cloth_red, draped, fresh, red_pixels, scene_with, with_positions


def test_each_side_is_lit_by_the_lights_on_its_side_and_the_underside_is_darker(renderer):
    scene = scene_with(wireframe=False).with_value("scene.floor", False)
    flat = draped(scene, sag=0.0)
    top_mask, top = cloth_red(fresh(renderer, flat, elevation=30.0))
    under_mask, under = cloth_red(fresh(renderer, flat, elevation=-30.0))
    assert top_mask.sum() > 2000 and under_mask.sum() > 2000  # seen from both sides
    # The sun is above: the underside has ambient light and the headlight only, so it is
    # clearly darker than the sunlit top, yet lit (not black).
    ratio = np.median(under) / np.median(top)
    assert 0.25 < ratio < 0.55 and np.median(under) > 40, ratio
    color = np.array(renderer.cloth_actor.GetProperty().GetDiffuseColor())
    back = np.array(renderer.cloth_actor.GetBackfaceProperty().GetDiffuseColor())
    np.testing.assert_allclose(back, BACK_SHADE * color, atol=2 / 255)  # 8-bit colours


def test_the_sheet_casts_a_shadow_on_the_ground(renderer):
    snap = draped(scene_with(wireframe=False))
    away = with_positions(snap, snap.positions + [40.0, 0.0, 0.0])  # far off, in the fog
    with_sheet, without = fresh(renderer, snap), fresh(renderer, away)
    darker = (without.astype(int) - with_sheet.astype(int)).sum(axis=2) > 30
    not_cloth = ~cloth_red(with_sheet)[0]
    assert (darker & not_cloth).sum() > 2000  # ground pixels the sheet shades


def test_the_ground_has_a_grid_so_height_reads(renderer):
    snap = draped(scene_with(wireframe=False))
    away = with_positions(snap, snap.positions + [40.0, 0.0, 0.0])
    img = fresh(renderer, away).astype(float).sum(axis=2)
    row = img[-20]  # the ground near the camera
    dips = (row[2:-2] < row[:-4] - 6) & (row[2:-2] < row[4:] - 6)
    assert dips.sum() >= 4  # crossing several grid lines
    textured = fresh(renderer, draped(scene_with(wireframe=False, ground_texture="maze")))
    assert renderer.ground.grid_actor.GetVisibility() == 0  # a texture already shows height
    assert red_pixels(textured) > 0


def test_a_tall_view_frames_the_whole_sheet(renderer):
    snap = draped(scene_with(wireframe=False))
    fresh(renderer, snap, size=(194, 240))  # what an 80×24 terminal's video was: 388×480
    matrix = renderer._pick_state[0]
    h = np.c_[snap.positions, np.ones(len(snap.positions))] @ matrix.T
    ndc = h[:, :2] / h[:, 3:]
    assert np.abs(ndc).max() < 0.95  # every particle inside the picture, with a margin
    wide = fresh(renderer, snap, size=(320, 240))
    camera = renderer.camera
    assert camera.view_distance(renderer.size) == camera.distance and red_pixels(wide) > 1000


def test_antialiasing_softens_a_stair_step_and_leaves_flat_areas_alone():
    img = np.zeros((40, 40, 3), np.uint8)
    for y in range(40):
        img[y, : y // 3] = 220  # a shallow diagonal edge: stair steps
    out = antialias(img)
    assert out.shape == img.shape and out.dtype == np.uint8
    changed = np.any(out != img, axis=2)
    assert changed.sum() >= 10
    between = (out[..., 0] > 20) & (out[..., 0] < 200)
    assert between.sum() >= 10  # intermediate shades along the steps
    assert not changed[:, 25:].any()  # far from the edge nothing moves
    flat = np.full((20, 30, 3), 90, np.uint8)
    assert np.array_equal(antialias(flat), flat)


def test_cells_smaller_than_a_pixel_are_drawn_thinned_and_look_the_same(renderer,
                                                                        monkeypatch):
    import cloth_tui.render.renderer as renderer_module

    scene = scene_with(wireframe=False).with_value("cloth.resolution", 128)
    snap = draped(scene)
    thinned = fresh(renderer, snap, size=(160, 120))  # a 128² sheet's cells are ~0.5 px here
    assert renderer.cloth.n_cells <= len(snap.model.triangles) // 3
    monkeypatch.setattr(renderer_module, "MIN_CELL_PX", 0.0)  # every triangle
    whole = renderer.render(snap)
    assert renderer.cloth.n_cells == len(snap.model.triangles)
    assert np.abs(thinned.astype(int) - whole.astype(int)).mean() < 1.0  # sub-pixel detail
    monkeypatch.undo()
    renderer.zoom(8.0)  # close up, cells are wide again: every triangle
    renderer.render(snap)
    assert renderer.cloth.n_cells == len(snap.model.triangles)
    wire = draped(scene_with(wireframe=True).with_value("cloth.resolution", 128))
    fresh(renderer, wire, size=(160, 120))
    assert renderer.cloth.n_cells == len(snap.model.triangles)  # the wireframe shows all


def test_a_strip_is_thinned_along_its_fine_side_only(renderer, monkeypatch):
    # 2 m × 0.5 m at 256 × 5: columns 8 mm apart (under a pixel at 160×120), rows 125 mm
    # apart (several pixels): every row is drawn, and a fraction of the columns.
    import cloth_tui.render.renderer as renderer_module

    scene = scene_with(wireframe=False).with_values({"cloth.size": [2.0, 0.5],
                                                     "cloth.resolution": [256, 5]})
    snap = draped(scene, sag=0.05)
    thinned = fresh(renderer, snap, size=(160, 120))
    rows, cols = renderer._detail_stride()
    assert rows == 1 and cols > 1
    drawn_cols = len(range(0, 256, cols)) + (255 % cols != 0)
    assert renderer.cloth.n_cells == 2 * 4 * (drawn_cols - 1)
    monkeypatch.setattr(renderer_module, "MIN_CELL_PX", 0.0)  # every triangle
    whole = renderer.render(snap)
    assert renderer.cloth.n_cells == len(snap.model.triangles)
    assert np.abs(thinned.astype(int) - whole.astype(int)).mean() < 1.0


def test_cells_under_two_pixels_are_drawn_thinned_and_narrow_folds_still_show(renderer,
                                                                             monkeypatch):
    """At 640×384 a 128² sheet's cells are 1.9 px: software GL pays per triangle there, so
    every other row is drawn (a quarter of the triangles), and folds three cells wide look
    as they do with every triangle."""
    import cloth_tui.render.renderer as renderer_module

    scene = scene_with(wireframe=False).with_value("cloth.resolution", 128)
    snap = draped(scene)
    x = snap.positions.copy()
    x[:, 1] += 0.004 * np.sin(2 * np.pi * x[:, 0] / (6 * snap.model.spacing))
    folded = with_positions(snap, x)
    thinned = fresh(renderer, folded, size=(640, 384)).astype(int)
    assert renderer.cloth.n_cells <= len(snap.model.triangles) // 3
    monkeypatch.setattr(renderer_module, "MIN_CELL_PX", 0.0)  # every triangle
    whole = renderer.render(folded).astype(int)
    assert renderer.cloth.n_cells == len(snap.model.triangles)
    assert np.abs(thinned - whole).mean() < 0.5
    mask, shade = cloth_red(whole.astype(np.uint8))
    assert mask.sum() > 10000 and shade.std() > 20  # the folds' light and shade
    assert np.corrcoef(thinned[..., 0][mask], shade)[0, 1] > 0.95


def test_the_poles_are_smooth_closed_solids_of_few_sides(renderer):
    """Software GL pays for the poles' long thin sides by the tiles they cross, not by their
    pixels: few sides, smooth-shaded so they still read as round, back faces culled."""
    from cloth_tui.render.props import POLE_SIDES

    snap = draped(scene_with(wireframe=False))
    fresh(renderer, snap, size=(320, 240))
    poles = renderer.poles
    assert POLE_SIDES <= 8 and poles.mesh.n_cells == 4 * (POLE_SIDES + 2)  # sides, two caps
    assert poles.actor.prop.GetBackfaceCulling()
    assert poles.actor.prop.interpolation.name.lower() in ("phong", "gouraud")
    img = fresh(renderer, with_positions(snap, snap.positions + [40.0, 0.0, 0.0])).astype(int)
    grey = ((np.abs(img[..., 0] - img[..., 1]) < 10) & (np.abs(img[..., 1] - img[..., 2]) < 10)
            & (img[..., 0] > 120))
    columns = np.flatnonzero(grey[120:200].any(axis=0))
    assert len(np.split(columns, np.flatnonzero(np.diff(columns) > 3) + 1)) == 4  # all four
    fresh(renderer, draped(snap.scene.with_value("cloth.size", 2.0)))  # what is drawn moves
    x0, x1 = poles.actor.mapper.GetInput().GetBounds()[:2]
    assert x1 - x0 > 2.0
    renderer.update_scene(snap.scene)


def test_poles_stand_only_under_the_corners_a_pin_holds(renderer):
    """The default scene hangs from two clips at the corners of one edge: two poles, under
    those corners; a sheet held by no corner has none."""
    from cloth_tui.render.props import POLE_SIDES
    from cloth_tui.scene_files import load

    from cloth_tui.sim.run.runner import Simulation

    scene = load("default").with_value("appearance.wireframe", False)
    snap = Simulation(scene).snapshot()  # (draped's model has no [[pins]])
    fresh(renderer, snap)
    poles = renderer.poles
    assert poles.actor.GetVisibility() and poles.mesh.n_cells == 2 * (POLE_SIDES + 2)
    held = snap.model.rest_positions[[0, snap.model.nx - 1]]
    x0, x1, _, y1, z0, z1 = poles.mesh.bounds
    assert np.allclose([x0, x1], [held[:, 0].min(), held[:, 0].max()], atol=0.02)
    assert np.allclose([z0, z1], held[0, 2], atol=0.02) and np.isclose(y1, held[0, 1])
    middle = scene.with_values({"pins": [{"rows": [5, 5], "cols": [5, 10]}]})
    fresh(renderer, Simulation(middle).snapshot())
    assert not poles.actor.GetVisibility()
    renderer.update_scene(scene_with())
