"""The wireframe reads as wires at the terminal preview's size (a 26² and a 64² sheet at
228×184, seen as the half-blocks show it, 2×2 pixels to a cell), and keeps the whole mesh
where the cells are large enough for it."""

import numpy as np
import pytest

from cloth_tui.render.geometry import triangle_edges
from cloth_tui.render.wire import WIRE_MESH_CELL_PX, grid_gaps_px, wire_edges, wire_look
from cloth_tui.sim.collision.surface import grid_cell_triangles

from .helpers import draped, red_pixels, scene_with


def _halved(img: np.ndarray) -> np.ndarray:
    """What a half-block cell shows: the mean of 2×2 rendered pixels."""
    h, w = img.shape[0] // 2 * 2, img.shape[1] // 2 * 2
    return img[:h, :w].reshape(h // 2, 2, w // 2, 2, 3).mean(axis=(1, 3))


def _red(img: np.ndarray) -> np.ndarray:
    r, g, b = (img[..., k] for k in range(3))
    return (r > 110) & (r > 2 * g) & (r > 2 * b)


@pytest.mark.parametrize("resolution", [26, 64])
def test_the_wireframe_shows_through_at_the_preview_size(renderer, resolution):
    renderer.resize(228, 184)
    shown = []
    for wireframe in (False, True):
        scene = scene_with(wireframe=wireframe).with_value("cloth.resolution", resolution)
        renderer.update_scene(scene)
        renderer.reset_camera()
        shown.append(_halved(renderer.render(draped(scene))))
    sheet = _red(shown[0])
    assert sheet.sum() > 500
    through = 1.0 - _red(shown[1])[sheet].mean()  # the sheet's cells not red: gaps
    assert through > 0.25, f"only {through:.0%} of the sheet shows between the wires"
    assert red_pixels(shown[1].astype(np.uint8)) > 200  # and the wires themselves are there
    renderer.update_scene(scene_with())
    renderer.resize(160, 120)


def test_large_cells_draw_the_whole_mesh_small_ones_spaced_grid_lines():
    nz, nx = 6, 9  # a rectangle: rows and columns of different counts
    edges = triangle_edges(grid_cell_triangles(nx, np.arange(nz), np.arange(nx)))
    assert len(wire_edges(edges, (nz, nx), wire_look(WIRE_MESH_CELL_PX, WIRE_MESH_CELL_PX))) \
        == len(edges)
    look = wire_look(2.0, 8.0)  # rows 2 px apart, columns 8: every 4th row, every column
    assert look == (4, 1, False, 2.0)
    drawn = wire_edges(edges, (nz, nx), look)
    rows, cols = drawn // nx, drawn % nx
    along_row = rows[:, 0] == rows[:, 1]
    assert set(rows[along_row, 0]) == {0, 4, 5}  # kept rows, the last one always
    assert set(cols[~along_row, 0]) == set(range(nx))
    assert (cols[~along_row, 0] == cols[~along_row, 1]).all()  # no diagonals
    assert len(drawn) == 3 * (nx - 1) + nx * (nz - 1)
    torn = edges[~((edges[:, 0] == 0) & (edges[:, 1] == 1))]  # a tear on the first row
    assert len(wire_edges(torn, (nz, nx), look)) == len(drawn) - 1


def test_grid_gaps_are_measured_on_screen():
    nz, nx = 3, 4
    x, z = np.meshgrid(np.arange(nx, dtype=float), np.arange(nz, dtype=float))
    positions = np.c_[x.ravel(), np.zeros(nx * nz), z.ravel()]  # row = z, column = x
    matrix = np.diag([0.1, 1.0, 0.05, 1.0])  # x → 0.1 NDC per metre, z → 0.05
    rows_px, columns_px = grid_gaps_px(matrix, positions, (nz, nx), (200, 100))
    assert rows_px == 0.0 and columns_px == 10.0  # z does not show on screen: rows collapse
    assert wire_look(rows_px, columns_px).row_stride > 1000
