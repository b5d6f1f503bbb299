"""ClothModel: what does not change while a sheet simulates.

Grid topology (grid.py: nz rows of nx particles, particle (row i, column j) at index
i*nx + j), rest lengths, constraint families in a conflict-free colouring for Gauss-Seidel
projection, pins and masses. The sheet starts flat at height `cloth.height`.
"""

from __future__ import annotations

from dataclasses import dataclass, replace

import numpy as np

from .effects.forces import wave_rows
from .effects.pins import PinLayout, layout
from .fabric.build import Fabric, build_fabric, fabric_masses, refit_fabric
from .grid import (BENDING, FAMILIES, NUM_COLORS, SHEAR, STRUCTURAL, Grid, grid_colors,
                   grid_edges, grid_triangles)
from .solvers import registry

# (the grid's families and pairs, read from here by the model's users too)
__all__ = ["BENDING", "FAMILIES", "SHEAR", "STRUCTURAL", "ClothModel", "build_model",
           "grid_edges", "grid_triangles", "nearest_pins", "particle_masses", "pinned_indices",
           "refitted", "uses_tethers"]


@dataclass(frozen=True)
class ClothModel:
    nx: int                     # particles along x: the columns, the length of a row
    nz: int                     # particles along z: the rows
    width: float                # m, along x
    length: float               # m, along z
    rest_positions: np.ndarray  # (N, 3) float64, the flat start
    mass: np.ndarray            # (N,) kg per particle
    inv_mass: np.ndarray        # (N,) 1/kg, 0 for pinned particles
    pinned: np.ndarray          # (K,) int64 indices of pinned particles
    edges: np.ndarray           # (M, 2) int64 enabled constraints, sorted by colour
    rest_length: np.ndarray     # (M,) m
    family: np.ndarray          # (M,) int8: 0 structural, 1 shear, 2 bending
    color_offsets: np.ndarray   # (C+1,) int64: constraints of colour c are [off[c], off[c+1])
    triangles: np.ndarray       # (T, 3) int64, two per grid cell, for rendering and wind
    tether_pin: np.ndarray | None = None     # (N,) index into `pinned` of the nearest pin, −1 none
    tether_length: np.ndarray | None = None  # (N,) m, rest distance to that pin
    pin_layout: PinLayout | None = None  # where pins hold (offsets, keys) and soft pins (pins.py)
    fabric: Fabric | None = None  # the scene's [material] on this grid (fabric.py), or none

    @property
    def num_particles(self) -> int:
        return self.nx * self.nz

    @property
    def num_constraints(self) -> int:
        return len(self.edges)

    @property
    def shape(self) -> tuple[int, int]:
        """(nz, nx): positions reshape to shape + (3,), rows first."""
        return self.nz, self.nx

    @property
    def spacing_x(self) -> float:
        return self.width / (self.nx - 1)

    @property
    def spacing_z(self) -> float:
        return self.length / (self.nz - 1)

    @property
    def spacing(self) -> float:
        """The finer of the two grid spacings (m): the scale below which particles are
        neighbours, for collision distances and the render's cell size."""
        return min(self.spacing_x, self.spacing_z)

    @property
    def extent(self) -> float:
        """The longer side (m)."""
        return max(self.width, self.length)


def pinned_indices(nx: int, nz: int, mode: str, seed: int = 0,
                   fraction: float = 0.05) -> np.ndarray:
    """The pinned particles of each mode on an nz-row, nx-column grid. Edges are rows or
    columns: one_edge = row 0 (the far edge, z = −length/2, nx particles); two_edges = rows 0
    and nz−1; four_edges = the whole border; random = `fraction` of all particles, chosen by
    `seed`."""
    idx = np.arange(nx * nz).reshape(nz, nx)
    if mode == "none":
        sel = np.zeros(0, np.int64)
    elif mode == "corners":
        sel = np.array([idx[0, 0], idx[0, -1], idx[-1, 0], idx[-1, -1]])
    elif mode == "one_edge":
        sel = idx[0, :]
    elif mode == "two_edges":
        sel = np.concatenate([idx[0, :], idx[-1, :]])
    elif mode == "four_edges":
        sel = np.concatenate([idx[0, :], idx[-1, :], idx[1:-1, 0], idx[1:-1, -1]])
    elif mode == "random":
        rng = np.random.default_rng(seed)
        count = int(round(fraction * nx * nz))
        sel = rng.choice(nx * nz, size=count, replace=False) if count else np.zeros(0, np.int64)
    else:
        raise ValueError(f"unknown pin mode {mode!r}")
    return np.unique(np.asarray(sel, dtype=np.int64))


MAX_TETHER_PAIRS = 50_000_000  # particles × pins searched; beyond it, a sample of the pins


def nearest_pins(rest: np.ndarray, pins: np.ndarray, seed: int) -> tuple:
    """For each particle, the nearest pin on the flat rest sheet (the geodesic distance, since
    the sheet starts flat) and that distance. With very many pins only a seeded sample is
    searched, which keeps the result a valid (slightly longer) upper bound."""
    if len(pins) * len(rest) > MAX_TETHER_PAIRS:
        keep = max(1, MAX_TETHER_PAIRS // len(rest))
        pins = np.sort(np.random.default_rng(seed).choice(pins, keep, replace=False))
        sampled = True
    else:
        sampled = False
    p = rest[pins]
    nearest = np.empty(len(rest), np.int64)
    dist = np.empty(len(rest))
    chunk = max(1, 4_000_000 // max(1, len(pins)))
    for lo in range(0, len(rest), chunk):
        d2 = ((rest[lo:lo + chunk, None, :] - p[None, :, :]) ** 2).sum(axis=2)
        k = d2.argmin(axis=1)
        nearest[lo:lo + chunk] = k
        dist[lo:lo + chunk] = np.sqrt(d2[np.arange(len(k)), k])
    return nearest, dist, pins if sampled else None


def uses_tethers(behavior, material=None) -> bool:
    """Tethers serve the solvers whose spec says so (the position-based ones), and only a
    sheet (some constraint family on) is inextensible enough for its pins to bound its
    particles. With springs, projecting positions the integrator then keeps moving adds
    energy (the divergence guard rightly rejects it with implicit Euler). A sheet that may
    tear has none: a tether holds each particle within its flat-sheet distance of a pin, so
    no pull could stretch the sheet to tearing, and a torn flap would hang on by nothing.
    A material has none either: a tether is no force of the fabric's, and would hold its
    particles from stretching as the fabric does."""
    return (material is None and behavior.tethers and registry.spec(behavior.solver).tethers
            and not behavior.tear and (behavior.structural or behavior.shear or behavior.bending))


def particle_masses(nx: int, nz: int, total: float, mass_model: str = "area") -> np.ndarray:
    """Lumped masses of an nz-row, nx-column grid summing to `total`. "area": each particle
    carries the area of its dual cell (interior 1, edge ½, corner ¼ of a cell; all cells are
    alike), so a uniform load such as wind accelerates every part of the sheet alike;
    "uniform": the original's equal masses."""
    if mass_model == "uniform":
        return np.full(nx * nz, total / (nx * nz))
    if mass_model != "area":
        raise ValueError(f"unknown mass model {mass_model!r}")
    row_share, col_share = np.ones(nz), np.ones(nx)
    row_share[[0, -1]] = 0.5  # a border row or column has half a cell on its outer side
    col_share[[0, -1]] = 0.5
    cell = total / ((nz - 1) * (nx - 1))  # the (nz−1)(nx−1) cells cover the sheet
    return (cell * np.outer(row_share, col_share)).ravel()


# The [cloth] and [behavior] keys build_model reads (tests/sim/test_model.py records them):
# a new value of one is a new sheet, where other keys only retune the step. Whether tethers
# are built also reads the solver and tearing (uses_tethers), compared on their own.
MODEL_KEYS = frozenset(
    {("cloth", k) for k in ("size", "resolution", "pinned", "pin_fraction", "mass",
                            "mass_model", "height")}
    | {("behavior", k) for k in ("structural", "shear", "bending", "seed", "tethers", "wave")})


def build_model(cloth, behavior, pin_groups=(), material=None) -> ClothModel:
    """Build the model from the scene's [cloth] and [behavior] sections, its [[pins]] and
    its material (materials.schema.Material, or None for the original's unitless keys).
    A material replaces cloth.mass by density × area and the distance constraints'
    families by its own: structural edges with an α each, shear cells and bending stencils
    (fabric.py); diagonal and two-apart distance constraints are then not built."""
    nx, nz = cloth.grid_shape()
    width, length = cloth.dimensions()
    grid = Grid(nx=nx, nz=nz, width=width, length=length)
    rest = grid.rest_positions(cloth.height)

    families = (behavior.structural, behavior.shear, behavior.bending)
    if material is not None:
        families = (behavior.structural, False, False)
    edges, family = grid_edges(nx, nz, families)
    colors = grid_colors(edges, nx)
    order = np.argsort(colors, kind="stable")
    edges, family, colors = edges[order], family[order], colors[order]
    counts = (np.bincount(colors, minlength=NUM_COLORS) if len(colors)
              else np.zeros(0, np.int64))
    offsets = np.concatenate([[0], np.cumsum(counts[counts > 0])]).astype(np.int64)
    rest_length = np.linalg.norm(rest[edges[:, 0]] - rest[edges[:, 1]], axis=1)

    pins = pinned_indices(nx, nz, cloth.pinned, behavior.seed, cloth.pin_fraction)
    held = [(f"cloth.pinned = \"{cloth.pinned}\"", pins)]
    if behavior.wave:
        # The wave drives the near edge (row nz−1) and holds the far edge (row 0): both pinned.
        held.append(("behavior.wave", np.concatenate(wave_rows(nx, nz))))
    pins, pin_layout = layout(held, list(pin_groups), rest, nz, nx)
    if not pin_groups:
        pin_layout = None  # every pin held in place: the model's `pinned` says it all
    fabric = None if material is None else build_fabric(material, grid, edges, behavior.shear,
                                                        behavior.bending)
    mass = (particle_masses(nx, nz, cloth.mass, cloth.mass_model) if fabric is None
            else fabric_masses(material, grid))
    inv_mass = 1.0 / mass
    inv_mass[pins] = 0.0
    tether_pin = tether_length = None
    if uses_tethers(behavior, material) and len(pins):
        near, tether_length, sample = nearest_pins(rest, pins, behavior.seed)
        # index into `pins` (the model's pinned array), whichever subset was searched
        tether_pin = near if sample is None else np.searchsorted(pins, sample[near])
        tether_pin[pins] = -1
    for arr in (rest, mass, inv_mass, pins, edges, rest_length, family, offsets):
        arr.setflags(write=False)
    return ClothModel(nx=nx, nz=nz, width=width, length=length, rest_positions=rest,
                      mass=mass, inv_mass=inv_mass, pinned=pins,
                      edges=np.ascontiguousarray(edges), rest_length=rest_length,
                      family=family, color_offsets=offsets, triangles=grid_triangles(nx, nz),
                      tether_pin=tether_pin, tether_length=tether_length,
                      pin_layout=pin_layout, fabric=fabric)


def refitted(model: ClothModel, cloth, material=None) -> ClothModel:
    """The same sheet with new numbers: the masses of cloth.mass (or of the material's
    density) and the material's α per constraint, for a scene that changed only those
    (params.same_structure). Every stage holds the model's mass arrays, so the new masses
    are written into them (held particles keep inverse mass 0); the fabric is a new one on
    the same constraints."""
    fabric = None if model.fabric is None else refit_fabric(model.fabric, material, model.edges)
    mass = (particle_masses(model.nx, model.nz, cloth.mass, cloth.mass_model) if fabric is None
            else fabric_masses(material, fabric.grid))
    inv_mass = 1.0 / mass
    inv_mass[model.pinned] = 0.0
    for arr, new in ((model.mass, mass), (model.inv_mass, inv_mass)):
        arr.setflags(write=True)
        arr[:] = new
        arr.setflags(write=False)
    return model if fabric is None else replace(model, fabric=fabric)
