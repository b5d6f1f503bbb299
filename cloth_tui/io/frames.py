"""What a bake writer is given each frame, the contract every writer keeps, and the faces a
torn sheet shows."""

from __future__ import annotations

from dataclasses import dataclass
from typing import Protocol

import numpy as np

from ..sim.model import ClothModel
from ..sim.effects.tearing import intact_triangles, triangle_constraints


@dataclass(frozen=True)
class BakedFrame:
    """One frame of the run: `frame` counts from 1, `t` is the simulated time (s), `positions`
    (N, 3) the particles, `objects` the ObjectPose of every collision object at t, `alive`
    (M,) the constraints' intact flags (None: nothing torn)."""
    frame: int
    t: float
    positions: np.ndarray
    objects: tuple = ()
    alive: np.ndarray | None = None


class SheetFaces:
    """The triangles a frame of the sheet shows: all of the model's, or on a torn sheet those
    with no torn edge, as the renderer draws it (a tear is a gap, not a stretched face)."""

    def __init__(self, model: ClothModel):
        self.model = model
        self.all = np.asarray(model.triangles, dtype=np.int64)
        self.triangles = self.all
        self.torn = 0
        self._edge_index: np.ndarray | None = None

    def update(self, alive: np.ndarray | None) -> bool:
        """Take a frame's flags; True if its faces differ from the last frame's. Tearing only
        breaks constraints, and a restart heals them all, so the count of torn ones tells
        (the renderer's rule too)."""
        torn = 0 if alive is None else int(alive.size - np.count_nonzero(alive))
        if torn == self.torn:
            return False
        self.torn = torn
        if torn:
            if self._edge_index is None:
                self._edge_index = triangle_constraints(self.model)
            self.triangles = intact_triangles(self.model, alive, self._edge_index)
        else:
            self.triangles = self.all
        return True


class BakeWriter(Protocol):
    """Frames in, files out. A writer keeps what it has written readable at all times (a
    SIGKILL loses at most the frames since its last save); `close` finishes the output."""

    def write(self, frame: BakedFrame) -> None:
        ...

    def close(self) -> None:
        ...
