"""A frame's fixed work, independent of the sheet: the picture read back into one kept buffer
(the same pixels plotter.screenshot gives), no clipping-range search over every actor's
bounds, anti-aliasing that reads a flipped view in place."""

import numpy as np

from cloth_tui.render.antialias import antialias

from .helpers import SPHERE, draped, scene_with


def test_read_back_is_the_screenshot_and_reuses_its_buffer(renderer):
    renderer.resize(161, 97)  # odd sizes: no row padding or off-by-one in the read
    renderer.update_scene(scene_with(wireframe=False))
    renderer.reset_camera()
    snap = draped(scene_with(wireframe=False), objects=(SPHERE,))
    image = renderer.render(snap)
    pixels = renderer.read_pixels()
    shot = renderer.plotter.screenshot(return_img=True)[..., :3]
    assert pixels.shape == (97, 161, 3) and pixels.dtype == np.uint8
    assert np.array_equal(pixels, shot)  # same rows, top first, same colours
    assert np.array_equal(image, antialias(shot))
    renderer.render(draped(scene_with(wireframe=False), sag=0.1, objects=(SPHERE,)))
    assert np.shares_memory(pixels, renderer.read_pixels())  # no new buffer per frame


def test_a_frame_does_not_search_the_actors_for_a_clipping_range(renderer, monkeypatch):
    """The camera sets its clipping range from the scene's size; recomputing it from every
    actor's bounds first (PyVista's camera setters do) is wasted work each frame."""
    renderer.resize(64, 48)
    renderer.reset_camera()
    resets = []
    monkeypatch.setattr(renderer.plotter.renderer, "reset_camera_clipping_range",
                        lambda: resets.append(1))
    snap = draped(scene_with())
    renderer.render(snap)
    renderer.orbit(10.0, 5.0)
    renderer.zoom(1.2)
    renderer.render(snap)
    assert resets == []
    near, far = renderer.plotter.camera.GetClippingRange()
    assert 0 < near < renderer.camera.view_distance(renderer.size) < far


def test_antialias_reads_a_flipped_view_as_its_copy():
    rng = np.random.default_rng(3)
    picture = rng.integers(0, 256, (40, 50, 3), dtype=np.uint8)
    picture[10:30, 10:30] = 200  # flat areas and edges both
    flipped = picture[::-1]
    assert np.array_equal(antialias(flipped), antialias(np.ascontiguousarray(flipped)))
    assert np.array_equal(antialias(flipped)[0, 0], flipped[0, 0])  # borders copied


def test_a_frame_allocates_no_array_of_the_sheets_size(renderer, monkeypatch):
    """Points, normals, the finite check, the shadow and the picking state: nothing of the
    sheet's size is allocated (the snapshot's own positions serve picking; they never
    change after), and the shadow works in place (it allocated ~0.1 MB a frame)."""
    import tracemalloc

    import cloth_tui.render.renderer as renderer_module

    monkeypatch.setattr(renderer_module, "MIN_CELL_PX", 0.0)
    scene = scene_with(wireframe=False).with_value("cloth.resolution", 128)
    first = draped(scene)
    renderer.resize(16, 12)
    renderer.update_scene(scene)
    renderer.reset_camera()
    renderer.render(first)
    second = draped(scene, sag=0.1, model=first.model)
    tracemalloc.start()
    renderer.render(second)
    peak = tracemalloc.get_traced_memory()[1]
    tracemalloc.stop()
    assert peak < 0.1 * second.positions.nbytes
    k = 128 * 64 + 64  # the middle particle, picked where the last frame drew it
    assert renderer.screen_delta_to_world(k, 0.0, 0.0) is not None


def test_drawable_refuses_nan_inf_and_far_points():
    from cloth_tui.render.geometry import drawable

    x = np.zeros((5, 3))
    assert drawable(x, 1e6)
    for bad in (np.nan, np.inf, -np.inf, 2e6):
        y = x.copy()
        y[3, 1] = bad
        assert not drawable(y, 1e6)
