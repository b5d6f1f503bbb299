"""What a bake writer is given each frame, and the contract every writer keeps."""

from __future__ import annotations

from dataclasses import dataclass
from typing import Protocol

import numpy as np


@dataclass(frozen=True)
class BakedFrame:
    """One frame of the run: `frame` counts from 1, `t` is the simulated time (s), `positions`
    (N, 3) the particles, `objects` the ObjectPose of every collision object at t."""
    frame: int
    t: float
    positions: np.ndarray
    objects: tuple = ()


class BakeWriter(Protocol):
    """Frames in, files out. A writer keeps what it has written readable at all times (a
    SIGKILL loses at most the frames since its last save); `close` finishes the output."""

    def write(self, frame: BakedFrame) -> None:
        ...

    def close(self) -> None:
        ...
