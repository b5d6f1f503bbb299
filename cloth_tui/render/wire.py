"""Which of the sheet's edges the wireframe draws, and how thick, for the size its grid cells
have on screen. Every edge (the diagonals too) at 1 px needs cells of WIRE_MESH_CELL_PX: in a
smaller picture (the terminal preview, ~228×184, where a 26² sheet's cells are ~4.6 px, and
half that across a sheet seen at a slant) the lines and the gaps between them blur into a
solid sheet with pinholes. There the wireframe is the grid's own lines, every k-th row and
every m-th column, 2 px wide and at least WIRE_CELL_PX apart on screen, so it still reads as
wires once the terminal halves the picture again. Rows and columns are spaced apart
separately: a sheet seen from the side foreshortens one of them only."""

from __future__ import annotations

import math
from typing import NamedTuple

import numpy as np

from ..sim.collision.surface import thinned_rows

WIRE_MESH_CELL_PX = 10.0  # cells at least this wide each way: the whole mesh, 1 px lines
WIRE_CELL_PX = 8.0        # else: drawn grid lines at least this far apart…
WIRE_THICK_PX = 2.0       # …and this wide


class WireLook(NamedTuple):
    row_stride: int     # grid rows between drawn row lines
    column_stride: int  # grid columns between drawn column lines
    diagonals: bool     # the triangles' diagonals too (the whole mesh)
    width: float        # px


def _stride(px: float) -> int:
    return max(1, math.ceil(WIRE_CELL_PX / max(px, 1e-9)))


def wire_look(row_gap_px: float, column_gap_px: float) -> WireLook:
    """For grid rows `row_gap_px` apart on screen and columns `column_gap_px` apart."""
    if min(row_gap_px, column_gap_px) >= WIRE_MESH_CELL_PX:
        return WireLook(1, 1, True, 1.0)
    return WireLook(_stride(row_gap_px), _stride(column_gap_px), False, WIRE_THICK_PX)


def grid_gaps_px(matrix: np.ndarray, positions: np.ndarray, shape: tuple[int, int],
                 size: tuple[int, int]) -> tuple[float, float] | None:
    """How far apart neighbouring rows and neighbouring columns of a sheet of `shape` (rows,
    columns) are drawn (the median over the sheet, in pixels), given the world → clip
    `matrix` of a render of `size`; None if the sheet is behind the camera."""
    rows, cols = shape
    if min(rows, cols) < 2 or len(positions) != rows * cols:
        return None
    h = np.c_[positions, np.ones(len(positions))] @ matrix.T
    if not (h[:, 3] > 1e-9).all():
        return None
    xy = h[:, :2] / h[:, 3:4] * (0.5 * np.asarray(size, float))  # NDC → pixels
    grid = xy.reshape(rows, cols, 2)
    row_gap = np.linalg.norm(grid[1:, :] - grid[:-1, :], axis=2)      # row i to row i+1
    column_gap = np.linalg.norm(grid[:, 1:] - grid[:, :-1], axis=2)   # column j to j+1
    gaps = float(np.median(row_gap)), float(np.median(column_gap))
    return gaps if all(math.isfinite(g) for g in gaps) else None


def wire_edges(edges: np.ndarray, shape: tuple[int, int], look: WireLook) -> np.ndarray:
    """The edges (E, 2) of a particle grid of `shape` (rows, columns; index = row·columns +
    column) that `look` draws:
    along kept rows and columns, and the diagonals if it draws them. Edges missing from
    `edges` (a tear) stay missing."""
    if look.diagonals or len(edges) == 0:
        return edges
    a, b = edges[:, 0], edges[:, 1]
    rows, cols = shape
    row_a, col_a, row_b, col_b = a // cols, a % cols, b // cols, b % cols
    kept_rows = np.zeros(rows, bool)
    kept_rows[thinned_rows(rows, look.row_stride)] = True
    kept_columns = np.zeros(cols, bool)
    kept_columns[thinned_rows(cols, look.column_stride)] = True
    along_row = (row_a == row_b) & kept_rows[row_a]
    along_column = (col_a == col_b) & kept_columns[col_a]
    return edges[along_row | along_column]
