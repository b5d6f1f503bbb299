"""Which of the sheet's edges the wireframe draws, and how thick, for the size its grid cells
have on screen. Every edge (the diagonals too) at 1 px needs cells of WIRE_MESH_CELL_PX: in a
smaller picture (the terminal preview, ~228×184, where a 26² sheet's cells are ~4.6 px) the
lines and the gaps between them blur into a solid sheet with pinholes. There the wireframe is
the grid's own lines, every stride-th row and column, 2 px wide and at least WIRE_CELL_PX
apart, so it still reads as wires once the terminal halves the picture again."""

from __future__ import annotations

import math
from typing import NamedTuple

import numpy as np

from ..sim.surface import thinned_rows

WIRE_MESH_CELL_PX = 10.0  # cells at least this wide: the whole mesh, 1 px lines
WIRE_CELL_PX = 8.0        # else: drawn grid lines at least this far apart…
WIRE_THICK_PX = 2.0       # …and this wide


class WireLook(NamedTuple):
    stride: int        # grid rows (and columns) between drawn lines
    diagonals: bool    # the triangles' diagonals too (the whole mesh)
    width: float       # px


def wire_look(cell_px: float) -> WireLook:
    if cell_px >= WIRE_MESH_CELL_PX:
        return WireLook(1, True, 1.0)
    return WireLook(max(1, math.ceil(WIRE_CELL_PX / max(cell_px, 1e-9))), False,
                    WIRE_THICK_PX)


def wire_edges(edges: np.ndarray, n: int, look: WireLook) -> np.ndarray:
    """The edges (E, 2) of an n×n particle grid (index = row·n + column) that `look` draws:
    along kept rows and columns, and the diagonals if it draws them. Edges missing from
    `edges` (a tear) stay missing."""
    if look.diagonals or len(edges) == 0:
        return edges
    a, b = edges[:, 0], edges[:, 1]
    row_a, col_a, row_b, col_b = a // n, a % n, b // n, b % n
    kept = np.zeros(n, bool)
    kept[thinned_rows(n, look.stride)] = True
    along_row = (row_a == row_b) & kept[row_a]
    along_column = (col_a == col_b) & kept[col_a]
    return edges[along_row | along_column]
