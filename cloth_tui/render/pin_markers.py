"""Small dots on the held particles (pins, pin groups, the app's pinned grabs), drawn in the
app's preview so a user sees what holds the sheet; `appearance.show_pins` turns them off.
Renders from the command line leave them out (Renderer's `markers`)."""

from __future__ import annotations

import numpy as np

MARKER_COLOR = "#ffd21f"  # yellow: apart from the cloth's reds, the ground's blues and fog
MARKER_PX = 6.0           # point size, pixels


def held_particles(model) -> np.ndarray:
    """Every particle a pin holds: the model's pinned ones, and soft-pinned ones."""
    lay = model.pin_layout
    if lay is None or not len(lay.soft.index):
        return np.asarray(model.pinned)
    return np.union1d(model.pinned, lay.soft.index)


class PinMarkers:
    def __init__(self, pv, plotter):
        self.pv = pv
        self.mesh = pv.PolyData(np.zeros((1, 3)))
        self.actor = plotter.add_mesh(self.mesh, color=MARKER_COLOR, style="points",
                                      point_size=MARKER_PX, render_points_as_spheres=True,
                                      lighting=False, reset_camera=False)
        self.actor.SetVisibility(False)
        self._model = None
        self._held = np.zeros(0, np.int64)

    def update(self, model, positions: np.ndarray, visible: bool) -> None:
        if model is not self._model:
            self._model = model
            self._held = held_particles(model)
        show = visible and len(self._held) > 0
        self.actor.SetVisibility(show)
        if not show:
            return
        points = positions[self._held]
        if len(points) != self.mesh.n_points:
            self.mesh.copy_from(self.pv.PolyData(points.copy()))
        else:
            self.mesh.points[...] = points
            self.mesh.Modified()
