"""The view's camera: an orbit about a target on the sheet, by azimuth, elevation and
distance, kept above the floor and fitted to the view's aspect. NumPy state; `apply` sets a
VTK camera from it."""

from __future__ import annotations

import math

import numpy as np

from .props import GROUND_RADIUS

VIEW_ANGLE = 30.0          # degrees, the original's PerspectiveCamera(30, ...)
HOME_AZIMUTH = 34.0        # degrees: the original camera at (1000, 50, 1500), seen from the side
HOME_ELEVATION = 20.0      # degrees: raised a little so the sheet's top is visible
HOME_DISTANCE = 3.0        # m, for a 1 m sheet
FIT_ASPECT = 1.0           # views narrower than this move the camera back so the sheet fits
MAX_ELEVATION = 85.0       # degrees up or down: nearer the vertical the view-up flips
ABOVE_FLOOR = 0.05         # m for a 1 m sheet: the lowest the camera goes above the floor


class OrbitCamera:
    """Where the view looks from. `cloth` and `section` are the scene's [cloth] and [scene]
    sections, which place the sheet and the floor."""

    def __init__(self):
        self.azimuth, self.elevation, self.distance = HOME_AZIMUTH, HOME_ELEVATION, HOME_DISTANCE
        self.target = np.zeros(3)

    def home(self, cloth, section) -> None:
        """The start view of a sheet: from the side, a little above, the sheet in view."""
        extent = cloth.extent()  # the longer side: a banner fits the view as a square of its width
        scale = max(extent, 0.25)
        self.azimuth, self.elevation = HOME_AZIMUTH, HOME_ELEVATION
        self.distance = HOME_DISTANCE * scale
        bottom = (max(section.floor_height, cloth.height - extent) if section.floor
                  else cloth.height - extent)
        self.target = np.array([0.0, 0.5 * (cloth.height + bottom) + 0.05 * scale, 0.0])

    def orbit(self, d_azimuth: float, d_elevation: float) -> None:
        self.azimuth = (self.azimuth + float(d_azimuth)) % 360.0
        self.elevation = float(np.clip(self.elevation + float(d_elevation),
                                       -MAX_ELEVATION, MAX_ELEVATION))

    def zoom(self, factor: float) -> None:
        """factor > 1 moves closer."""
        if factor > 0 and math.isfinite(factor):
            self.distance = float(np.clip(self.distance / factor, 0.05, 200.0))

    def lowest_elevation(self, distance: float, cloth, section) -> float:
        """Degrees: the camera at this distance stays a little above the floor (from
        below, the ground hides the cloth and the picture turns upside down)."""
        if not section.floor:
            return -MAX_ELEVATION
        lowest_y = section.floor_height + ABOVE_FLOOR * max(cloth.extent(), 0.25)
        sine = (lowest_y - self.target[1]) / max(distance, 1e-9)
        return float(np.clip(math.degrees(math.asin(np.clip(sine, -1.0, 1.0))),
                             -MAX_ELEVATION, MAX_ELEVATION))

    def view_distance(self, size: tuple[int, int]) -> float:
        """The camera's real distance: `distance` in views at least FIT_ASPECT wide; in
        narrower ones (a tall preview or video) farther, by the aspect ratio, so what fits the
        width of a square view fits theirs (the horizontal field shrinks with the aspect)."""
        w, h = size
        return self.distance * max(1.0, FIT_ASPECT * h / w)

    def half_height(self, size: tuple[int, int]) -> float:
        """m: half the height the view spans at the target's distance."""
        return self.view_distance(size) * math.tan(math.radians(VIEW_ANGLE / 2))

    def apply(self, cam, size: tuple[int, int], cloth, section) -> None:
        """Set VTK camera `cam` to this view, for a picture of `size`."""
        distance = self.view_distance(size)
        # Zooming out (or a higher floor) can take a low camera under the floor, too.
        self.elevation = max(self.elevation, self.lowest_elevation(distance, cloth, section))
        az, el = math.radians(self.azimuth), math.radians(self.elevation)
        offset = distance * np.array([math.cos(el) * math.sin(az), math.sin(el),
                                      math.cos(el) * math.cos(az)])
        # VTK's own setters: PyVista's position setter also resets the clipping range from
        # every actor's bounds, a cost each frame for what the line below sets anyway.
        cam.SetFocalPoint(*self.target)
        cam.SetPosition(*(self.target + offset))
        cam.SetViewUp(0.0, 1.0, 0.0)
        cam.SetViewAngle(VIEW_ANGLE)
        far = distance + 2.0 * GROUND_RADIUS * max(1.0, cloth.extent())
        cam.SetClippingRange(max(0.01, 0.02 * distance), far)
