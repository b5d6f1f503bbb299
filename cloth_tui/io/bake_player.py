"""Playing a bake back: which of its frames shows now, and that frame as the same `Snapshot`
a simulation publishes, so the renderer draws it like a live one. Plain Python on a caller's
clock (`now`, seconds): the replay app drives it from a timer, tests with numbers."""

from __future__ import annotations

from ..scene import Scene
from ..sim.model import ClothModel, build_model
from ..sim.run.run_stats import RunStats
from ..sim.run.runner import Snapshot
from ..usage import UsageError
from .usd_read import UsdBake


def bake_model(bake: UsdBake, scene: Scene) -> ClothModel:
    """The sheet the recorded scene builds (faces, UVs, pins for drawing); bad input if its
    grid (when the bake records one) or its particle count is not the bake's."""
    model = build_model(scene.cloth, scene.behavior, scene.pins)
    if bake.grid is not None and bake.grid != (model.nx, model.nz):
        raise UsageError(f"{bake.path}: its cloth is a grid of {bake.grid[0]} × "
                         f"{bake.grid[1]} particles, its recorded scene makes {model.nx} × "
                         f"{model.nz}")
    points = len(bake.positions(bake.frames[0]))
    if points != model.num_particles:
        raise UsageError(f"{bake.path}: its cloth has {points} points, its recorded scene "
                         f"makes {model.num_particles}")
    flags = bake.flag_count  # a torn sheet's flags, one per constraint, in every frame
    if flags is not None and flags != model.num_constraints:
        raise UsageError(f"{bake.path}: its cloth has {flags} constraint flags, its "
                         f"recorded scene makes {model.num_constraints} constraints")
    return model


class BakePlayer:
    """A playhead over a bake's frames (`index` 0..count-1). Playing, the index follows the
    clock at the bake's own frame rate (frames are skipped when the caller is late, so the
    motion keeps its speed) and wraps round at the end."""

    def __init__(self, bake: UsdBake, scene: Scene):
        self.bake = bake
        self.scene = scene
        self.model = bake_model(bake, scene)
        self.index = 0
        self.playing = False
        self._anchor: tuple[float, int] = (0.0, 0)  # (now, index) when playing last began

    @property
    def count(self) -> int:
        return len(self.bake.frames)

    @property
    def frame(self) -> int:
        """The bake's frame number (its time code) at the playhead."""
        return self.bake.frames[self.index]

    @property
    def frame_rate(self) -> float:
        return self.bake.frame_rate

    @property
    def time(self) -> float:
        """Simulated seconds at the playhead (time code k is k frames in)."""
        return self.frame / self.frame_rate

    def seek(self, index: int, now: float) -> None:
        self.index = min(max(int(index), 0), self.count - 1)
        self._anchor = (now, self.index)

    def step(self, delta: int, now: float) -> None:
        """A frame step pauses, as in a video player: the frame stays to be looked at."""
        self.playing = False
        self.seek(self.index + delta, now)

    def play(self, now: float) -> None:
        if self.index == self.count - 1:
            self.index = 0  # play at the end starts again from the beginning
        self.playing = True
        self._anchor = (now, self.index)

    def pause(self) -> None:
        self.playing = False

    def toggle(self, now: float) -> None:
        if self.playing:
            self.pause()
        else:
            self.play(now)

    def advance(self, now: float) -> bool:
        """Move the playhead to where the clock says; True if it moved."""
        if not self.playing:
            return False
        t0, start = self._anchor
        # A timer ticking every 1/rate lands on frame boundaries: do not let rounding put a
        # tick just before one (the same frame twice, then a skipped one).
        index = (start + int((now - t0) * self.frame_rate + 1e-6)) % self.count
        moved = index != self.index
        self.index = index
        return moved

    def snapshot(self) -> Snapshot:
        frame = self.frame
        return Snapshot(self.bake.positions(frame), frame, self.time, RunStats(), self.model,
                        self.scene, self.bake.objects(frame), self.bake.alive(frame))
