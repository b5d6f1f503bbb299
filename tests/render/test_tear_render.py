"""A torn sheet is drawn with a gap: the triangles that lost an edge are gone."""

import dataclasses

import numpy as np

from cloth_tui.sim.state import ClothState
from cloth_tui.sim.effects.tearing import cut_between

from .helpers import draped, red_pixels, scene_with


def torn_across(snap):
    """The snapshot with the sheet cut along its middle row, edge to edge."""
    model = snap.model
    state = ClothState.from_model(model)
    n = model.nx
    row = n // 2
    assert cut_between(model, state, row * n, row * n + n - 1) > 0
    return dataclasses.replace(snap, alive=state.alive.copy())


def test_a_cut_removes_a_row_of_faces_and_shows_a_gap(renderer):
    renderer.resize(160, 120)
    whole = draped(scene_with(wireframe=False))
    renderer.update_scene(whole.scene)
    renderer.reset_camera()
    img_whole = renderer.render(whole)
    n = whole.model.nx
    assert renderer.cloth.n_cells == 2 * (n - 1) ** 2
    torn = torn_across(whole)
    img_torn = renderer.render(torn)
    assert renderer.cloth.n_cells == 2 * (n - 1) ** 2 - 2 * (n - 1)
    assert renderer.wire.n_lines < 3 * (n - 1) ** 2 + 2 * (n - 1)
    # the constraint lines (show_constraints) lose the torn constraints
    assert renderer.lines.n_lines == int(torn.alive.sum()) < whole.model.num_constraints
    assert renderer.lines.cell_data["rgb"].shape[0] == renderer.lines.n_lines
    # the gap: fewer cloth pixels, the background or ground showing through
    assert red_pixels(img_torn) < red_pixels(img_whole) - 20
    # a healed sheet (a restart: no torn constraints) has every face back
    renderer.render(whole)
    assert renderer.cloth.n_cells == 2 * (n - 1) ** 2
    assert np.isfinite(renderer.cloth.point_data["Normals"]).all()


def test_faces_are_rebuilt_only_when_the_torn_count_changes(renderer):
    snap = torn_across(draped(scene_with(wireframe=False)))
    renderer.render(snap)
    stamp = renderer.cloth.GetPolys().GetMTime()
    renderer.render(dataclasses.replace(snap, frame=snap.frame + 1))
    assert renderer.cloth.GetPolys().GetMTime() == stamp
    more = snap.alive.copy()
    more[np.flatnonzero(more)[:40]] = 0
    renderer.render(dataclasses.replace(snap, alive=more))
    assert renderer.cloth.GetPolys().GetMTime() != stamp


def test_a_torn_sheet_casts_no_shadow_under_its_gap(renderer):
    # Cut across the middle and pull the near half 0.5 m away: the ground between the halves
    # gets sun. (The coarse copy the whole sheet's shadow uses would span the gap.)
    from .helpers import cloth_red, fresh

    whole = draped(scene_with(wireframe=False))
    torn = torn_across(whole)
    n = whole.model.nx
    x = np.array(whole.positions).reshape(n, n, 3)
    x[n // 2 + 1:, :, 2] += 0.5
    apart = dataclasses.replace(torn, positions=x.reshape(-1, 3))
    bridged = dataclasses.replace(apart, alive=None)  # the same points, every face kept
    away = dataclasses.replace(bridged, positions=bridged.positions + [40.0, 0.0, 0.0])
    ground = fresh(renderer, away).astype(int)

    def shaded(img):
        darker = (ground - img.astype(int)).sum(axis=2) > 30
        return int((darker & ~cloth_red(img)[0]).sum())

    gap, no_gap = shaded(fresh(renderer, apart)), shaded(fresh(renderer, bridged))
    assert renderer.shadow.drawn == ((n, n), 0)
    assert no_gap - gap > 1000, (gap, no_gap)  # measured: 8.0k against 12.0k pixels
    fresh(renderer, apart)
    assert renderer.shadow.mesh.n_cells == renderer.cloth.n_cells  # the faces drawn
