import math

import numpy as np

from cloth_tui.render.geometry import hex_rgb
from cloth_tui.sim.protocols import ObjectPose
from cloth_tui.sim.collision.surface import vertex_normals

from .helpers import SPHERE, draped, red_pixels, scene_with, with_positions


def fresh(renderer, snap, size=(160, 120)):
    renderer.resize(*size)
    renderer.update_scene(snap.scene)
    renderer.reset_camera()
    return renderer.render(snap)


def test_default_render_is_a_real_picture(renderer):
    img = fresh(renderer, draped(scene_with()))
    assert img.shape == (120, 160, 3) and img.dtype == np.uint8
    assert img.std() > 20  # not blank
    assert red_pixels(img) > 300  # the red cloth is there
    fog = (hex_rgb("#cce0ff") * 255).astype(int)
    assert np.abs(img[0, 0].astype(int) - fog).max() <= 3  # sky is the fog colour


def test_wireframe_on_and_off_differ(renderer):
    # 320x240: at 160x120 the 26x26 wireframe is so dense it looks almost solid
    wire = fresh(renderer, draped(scene_with(wireframe=True)), (320, 240))
    solid = fresh(renderer, draped(scene_with(wireframe=False)), (320, 240))
    assert np.abs(wire.astype(int) - solid).mean() > 1.0


def test_appearance_keys_change_the_picture(renderer):
    base = fresh(renderer, draped(scene_with(wireframe=False)))
    changes = dict(cloth_color="#2040c0", ground_color="#a0a040", ground_emissive="#404040",
                   fog_color="#ffe0e0", show_constraints=True, cloth_texture="maze",
                   ground_texture="grass", cloth_specular="#ffffff")
    for name, value in changes.items():
        img = fresh(renderer, draped(scene_with(wireframe=False, **{name: value})))
        assert np.abs(img.astype(int) - base).mean() > 0.05, name


def test_constraints_are_coloured_by_family(renderer):
    img = fresh(renderer, draped(scene_with(show_constraints=True)))
    r, g, b = (img[..., k].astype(int) for k in range(3))
    assert ((g > 150) & (r < 100) & (b < 120)).sum() > 20  # shear green
    assert ((b > 180) & (r < 120) & (g < 150)).sum() > 20  # bending blue


def test_auto_rotate_orbits_each_frame(renderer):
    snap = draped(scene_with(auto_rotate=True, wireframe=False))
    a = fresh(renderer, snap)
    b = renderer.render(snap)
    assert np.abs(a.astype(int) - b).mean() > 0.1
    renderer.update_scene(scene_with())


def test_camera_controls(renderer):
    snap = draped(scene_with(wireframe=False))
    home = fresh(renderer, snap)
    renderer.orbit(40, 10)
    assert np.abs(renderer.render(snap).astype(int) - home).mean() > 1
    renderer.reset_camera()
    renderer.zoom(2.0)
    near = renderer.render(snap)
    assert red_pixels(near) > 2 * red_pixels(home)
    renderer.reset_camera()
    assert np.array_equal(renderer.render(snap), home)


def _camera_y(renderer) -> float:
    return renderer.plotter.camera.GetPosition()[1]


def test_orbiting_down_stops_above_the_floor_as_orbiting_up_stops(renderer):
    snap = draped(scene_with(wireframe=False))
    fresh(renderer, snap)
    floor = snap.scene.scene.floor_height
    for _ in range(12):  # far past the floor: ten degrees a press
        renderer.orbit(0, -10)
        assert _camera_y(renderer) > floor
    r, g, b = (renderer.render(snap)[..., k].astype(int) for k in range(3))
    underside = (r > 60) & (r > 2 * g) & (r > 2 * b)  # darker red: seen from below, lit above
    assert underside.sum() > 300  # the cloth is in view, not hidden under the ground
    low = renderer.camera.elevation
    renderer.zoom(1 / 4)  # farther out at the lowest angle: still above the floor
    assert _camera_y(renderer) > floor and renderer.camera.elevation > low
    for _ in range(12):
        renderer.orbit(0, 10)
    assert renderer.camera.elevation == 85.0
    renderer.reset_camera()


def test_without_a_floor_the_camera_orbits_below(renderer):
    snap = draped(scene_with(wireframe=False).with_value("scene.floor", False))
    fresh(renderer, snap)
    for _ in range(12):
        renderer.orbit(0, -10)
    assert renderer.camera.elevation == -85.0
    renderer.update_scene(scene_with())
    renderer.reset_camera()


def test_objects_are_drawn_and_moved_in_place(renderer):
    scene = scene_with(wireframe=False)
    without = fresh(renderer, draped(scene, sag=0.05))
    with_sphere = renderer.render(draped(scene, sag=0.05, objects=(SPHERE,)))
    actors = len(renderer.plotter.renderer.actors)
    moved = ObjectPose("sphere", {"radius": 0.25}, (0.6, -0.25, 0.0))
    elsewhere = renderer.render(draped(scene, sag=0.05, objects=(moved,)))
    assert len(renderer.plotter.renderer.actors) == actors  # moved, not re-added
    assert np.abs(with_sphere.astype(int) - without).mean() > 0.3
    assert np.abs(elsewhere.astype(int) - with_sphere).mean() > 0.3
    renderer.render(draped(scene))  # objects gone again
    assert len(renderer.plotter.renderer.actors) == actors - 1


def test_nan_positions_never_reach_vtk(renderer):
    snap = draped(scene_with(wireframe=False))
    good = fresh(renderer, snap)
    bad = np.array(snap.positions)
    bad[5] = np.nan
    bad[7, 1] = np.inf
    held = renderer.render(with_positions(snap, bad))
    assert np.array_equal(held, good)  # the last good positions are held


def test_odd_and_tiny_sizes(renderer):
    snap = draped(scene_with())
    for w, h in ((161, 97), (33, 1), (1, 1), (75, 241)):
        assert fresh(renderer, snap, (w, h)).shape == (h, w, 3)


def test_model_change_rebuilds_the_mesh(renderer):
    scene = scene_with(wireframe=False).with_value("cloth.resolution", 9)
    img = fresh(renderer, draped(scene))
    assert red_pixels(img) > 300


def project(renderer, point):
    m, _ = renderer._pick_state
    h = m @ np.r_[point, 1.0]
    x, y = h[0] / h[3], h[1] / h[3]
    return (x + 1) / 2, (1 - y) / 2


def test_pick_returns_the_particle_under_the_pointer(renderer):
    snap = draped(scene_with(wireframe=False), sag=0.02)
    fresh(renderer, snap, (320, 240))
    n = snap.model.nx
    for i, j in ((3, 3), (12, 20), (22, 5), (13, 13)):
        k = i * n + j
        u, v = project(renderer, snap.positions[k])
        assert renderer.pick(u, v) == k
        assert renderer.pick(u + 0.3 / 320, v - 0.3 / 240) == k  # a pointer a bit off
    assert renderer.pick(0.02, 0.02) is None  # the sky
    assert renderer.pick(math.nan, 0.5) is None


def test_vertex_normals_of_a_flat_sheet_point_up():
    snap = draped(scene_with(), sag=0.0)
    nrm = vertex_normals(snap.positions, snap.model.triangles)
    assert np.allclose(np.abs(nrm[:, 1]), 1.0)


def test_a_frame_updates_the_mesh_in_place_without_allocating_per_point(renderer,
                                                                        monkeypatch):
    """Points and normals are written into VTK's own arrays (normals by a compiled kernel):
    the only per-frame arrays of the sheet's size are the picking copy of the positions."""
    import tracemalloc

    import cloth_tui.render.renderer as renderer_module

    monkeypatch.setattr(renderer_module, "MIN_CELL_PX", 0.0)  # every triangle, even tiny
    scene = scene_with(wireframe=False).with_value("cloth.resolution", 128)
    first = draped(scene)
    fresh(renderer, first, (16, 12))
    normals = renderer.cloth.point_data["Normals"]
    second = draped(scene, sag=0.1, model=first.model)
    tracemalloc.start()
    renderer.render(second)
    peak = tracemalloc.get_traced_memory()[1]
    tracemalloc.stop()
    assert peak < 1.5 * second.positions.nbytes
    np.testing.assert_allclose(renderer.cloth.point_data["Normals"],
                               vertex_normals(second.positions, second.model.triangles),
                               atol=1e-5)
    np.testing.assert_allclose(renderer.cloth.points, second.positions, atol=1e-6)
    assert np.shares_memory(normals, renderer.cloth.point_data["Normals"])
