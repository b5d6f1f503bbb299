"""The app's view and pointer actions: orbit, zoom and reset the camera, move the crosshair,
bump the particle under the pointer or crosshair, and drag one with the mouse. A mixin of
`ClothApp`, which owns the renderer, the simulation thread and the preview."""

from __future__ import annotations

import time
from collections import deque
from typing import Any, Callable

from ..scene import Scene, SceneError
from ..sim.effects.pins import grid_shape
from ..sim.run.sim_thread import SimulationThread
from .bindings import BUMP_M, ORBIT_DEG, VIEW_SPAN, ZOOM_STEP
from .messages import PinResult
from .preview import Preview

RECENT_VIEW_S = 3.0  # view keys this recent are told of when a digit shows typing was meant


def typed_digit_notice(digit: str, recent: list[str]) -> str:
    """What to tell a user who typed a digit with no field focused."""
    done = f" The view keys typed with it acted: {', '.join(recent)}." if recent else ""
    return (f"'{digit}' typed with no field focused: click a field or press Tab to type a "
            f"value.{done} Press o to reset the view.")


def pin_where_it_is(particle: int, post: Callable[[PinResult], Any]) -> Callable[[Any], None]:
    """The pin gesture's command for the simulation thread: hold `particle` where the drag
    left it, and post what came of it."""
    def command(sim) -> None:
        where = sim.state.x[particle].copy()
        try:
            sim.pin(particle, where)
        except SceneError as e:
            post(PinResult(str(e), ok=False))
            return
        r, c = divmod(particle, grid_shape(sim.model)[1])
        at = ", ".join(f"{v:.3g}" for v in where)
        post(PinResult(f"particle [{r}, {c}] held at ({at}) m; r restores the scene's pins",
                       ok=True))
    return command


class ViewActions:
    """Needs from the app: `scene`, `sim`, `renderer` (or None), `preview`, `notify`,
    `post_message` and `_log_key`; keeps `_zoom`, `_grabbed` and `_cut_at` (the knife)."""

    scene: Scene
    sim: SimulationThread | None
    renderer: Any
    preview: Preview
    notify: Callable[..., None]
    post_message: Callable[..., Any]
    _log_key: Callable[[str], None]
    _zoom: float
    _grabbed: int | None
    _cut_at: int | None
    _view_log: deque[tuple[float, str]]  # (monotonic time, what a view key did)

    def _did(self, what: str) -> None:
        self._view_log.append((time.monotonic(), what))

    def recent_view_keys(self) -> list[str]:
        now = time.monotonic()
        return [what for t, what in self._view_log if now - t < RECENT_VIEW_S]

    def _place_crosshair(self) -> bool:
        """Put the crosshair on the particle nearest the middle of the sheet, by picking a
        coarse grid of image points (pick is cheap); of the points that pick it, the one
        nearest the picture's centre. False if no particle is visible yet."""
        nx, nz = self.scene.cloth.grid_shape()
        best, best_d = None, None
        for i in range(1, 24):
            for j in range(1, 24):
                uv = (i / 24, j / 24)
                p = self.renderer.pick(*uv)
                if p is None:
                    continue
                d = (abs(p // nx - (nz - 1) / 2) + abs(p % nx - (nx - 1) / 2),
                     (uv[0] - 0.5) ** 2 + (uv[1] - 0.5) ** 2)
                if best_d is None or d < best_d:
                    best, best_d = uv, d
        if best is None:
            return False
        self.preview.crosshair = best
        self.preview.move_crosshair(0, 0)
        return True

    def on_preview_grab(self, message: Preview.Grab) -> None:
        self._grabbed = self.renderer.pick(message.u, message.v) if self.renderer else None

    def on_preview_drag(self, message: Preview.Drag) -> None:
        """Move the grabbed particle with the pointer: in the camera's view plane at its
        depth, so the drag follows any orbit (the renderer's last camera, NumPy only). Before
        a first frame, a fixed front-view scale."""
        if self._grabbed is None:
            return
        d = None
        if self.renderer is not None:
            d = self.renderer.screen_delta_to_world(self._grabbed, message.du, message.dv)
        if d is None:
            span = VIEW_SPAN * self.scene.cloth.extent() / self._zoom
            aspect = message.width_px / max(message.height_px, 1)
            d = (message.du * span * aspect, -message.dv * span, 0.0)
        self._bump(self._grabbed, d)

    def on_preview_release(self, message: Preview.Release) -> None:
        if message.pin and self._grabbed is not None and self.sim is not None:
            self.sim.submit(pin_where_it_is(self._grabbed, self.post_message))
        self._grabbed = None

    def on_pin_result(self, message: PinResult) -> None:
        self.notify(message.text, title="Pinned" if message.ok else "Pin refused",
                    severity="information" if message.ok else "error",
                    timeout=4 if message.ok else 8)

    def on_preview_cut(self, message: Preview.Cut) -> None:
        """Cut the cloth from the particle the knife last passed to the one under it now
        (the renderer's last frame, NumPy only); off the sheet, the path starts anew."""
        here = self.renderer.pick(message.u, message.v) if self.renderer else None
        last, self._cut_at = (None if message.start else self._cut_at), here
        if self.sim is not None and last is not None and here is not None and here != last:
            self.sim.submit(lambda sim: sim.cut(last, here))

    def _bump(self, particle: int, d: tuple[float, float, float]) -> None:
        if self.sim is not None:
            self.sim.submit(lambda sim: sim.bump(particle, d))

    def action_bump(self, dx: float, dy: float, dz: float) -> None:
        if self.renderer is None:
            self.notify("no renderer: cannot tell which particle is under the pointer",
                        severity="warning")
            return
        u, v = self.preview.target
        particle = self.renderer.pick(u, v)
        if particle is None:
            where = "pointer" if self.preview.pointer is not None else "crosshair (move: h j k l)"
            self.notify(f"No particle under the {where}", severity="warning", timeout=1.5)
            return
        self._bump(particle, (dx * BUMP_M, dy * BUMP_M, dz * BUMP_M))
        self._log_key("bump")

    def action_pin(self) -> None:
        """The pin gesture from the keyboard, for terminals that do not report Ctrl with the
        mouse: the particle under the pointer or crosshair, where it is."""
        particle = self.renderer.pick(*self.preview.target) if self.renderer else None
        if particle is None:
            self.notify("No particle under the pointer or crosshair to pin", severity="warning",
                        timeout=1.5)
        elif self.sim is not None:
            self.sim.submit(pin_where_it_is(particle, self.post_message))

    def action_crosshair(self, dcol: int, drow: int) -> None:
        self.preview.move_crosshair(dcol, drow)

    def action_orbit(self, d_az: float, d_el: float) -> None:
        if self.renderer is not None:
            self.renderer.orbit(d_az * ORBIT_DEG, d_el * ORBIT_DEG)
            self._did({(-1, 0): "orbit left", (1, 0): "orbit right", (0, -1): "orbit down",
                       (0, 1): "orbit up"}.get((d_az, d_el), "orbit"))
            self._log_key("orbit")

    def action_zoom(self, direction: int) -> None:
        factor = ZOOM_STEP if direction > 0 else 1 / ZOOM_STEP
        self._zoom *= factor
        self._did("zoom in" if direction > 0 else "zoom out")
        if self.renderer is not None:
            self.renderer.zoom(factor)
            self._log_key("zoom")

    def action_reset_camera(self) -> None:
        self._zoom = 1.0
        if self.renderer is not None:
            self.renderer.reset_camera()
