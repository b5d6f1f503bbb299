"""One off-screen PyVista plotter, kept for the renderer's whole life, drawing snapshots of
the cloth in the original's look: red sheet above a bluish ground fading into light-blue fog,
poles under the held corners, translucent objects.

Not thread-safe and bound to its creating thread (VTK's GL context is): in the app only the
render service's thread uses it. `pick` and `screen_delta_to_world` are the exceptions: they
read the camera matrix and positions saved after the last render, in NumPy, so any thread may
call them.
"""

from __future__ import annotations

import math

import numpy as np

from ..sim.collision.surface import grid_cell_triangles, grid_uv, thinned_rows, vertex_normals
from .antialias import antialias_bottom_up
from .camera import OrbitCamera
from ..sim.effects.tearing import intact_triangles, triangle_constraints
from .geometry import (AMBIENT, HEADLIGHT_INTENSITY, LIGHT_COLOR, LIGHT_DIR, SUN_INTENSITY,
                       drawable, family_colors, hex_rgb, pick_nearest, triangle_edges,
                       view_plane_delta)
from .pin_markers import PinMarkers
from .probe import require_renderer
from .props import Ground, Objects, Poles
from .shadow import Shadow
from .textures import TextureCache
from .vtk_setup import pyvista_quiet
from .wire import grid_gaps_px, wire_edges, wire_look

AUTO_ROTATE_DEG = 0.4      # per rendered frame: one turn in 30 s at 30 fps (three.js's speed 2)
MIN_CELL_PX = 2.0          # grid cells drawn at least this wide on screen (see _detail_stride)
BACK_SHADE = 0.8           # the cloth's underside: its colour × this, so folds read
MAX_SIZE = 8192


def check_size(w, h) -> tuple[int, int]:
    w, h = int(w), int(h)
    if not (1 <= w <= MAX_SIZE and 1 <= h <= MAX_SIZE):
        raise ValueError(f"image size {w}x{h} is outside 1..{MAX_SIZE} pixels per side")
    return w, h


class Renderer:
    def __init__(self, scene, size=(640, 480), markers: bool = False):
        """`markers`: dots on the held particles (the app's preview; pin_markers.py)."""
        require_renderer()  # RendererUnavailable, not a segfault, where GL cannot start
        pv = pyvista_quiet()
        self.pv = pv
        self.size = check_size(*size)
        self.plotter = pv.Plotter(off_screen=True, window_size=self.size, lighting="none")
        # MSAA costs 4x per frame with Mesa's software GL (the usual case off-screen), VTK's
        # FXAA pass 12 ms at 640x384: anti-aliasing is a compiled pass over the picture read
        # back instead (antialias.py).
        self.plotter.ren_win.SetMultiSamples(0)
        self._pixels = pv.convert_array(np.zeros(0, np.uint8))  # _read_rgba's buffer, kept
        # Both sides of the sheet lit, each by the lights on its side (VTK flips a back
        # face's normal); the underside also has a darker shade of the colour (_style_cloth).
        self.plotter.renderer.SetTwoSidedLighting(True)
        light = pv.Light(position=tuple(LIGHT_DIR * 10.0), focal_point=(0, 0, 0),
                         color=tuple(LIGHT_COLOR), intensity=SUN_INTENSITY,
                         light_type="scene light")
        light.positional = False
        self.plotter.add_light(light)
        # A weak light from the camera so vertical faces (poles, hanging cloth) are not black.
        self.plotter.add_light(pv.Light(light_type="headlight",
                                                 intensity=HEADLIGHT_INTENSITY))
        self.ground = Ground(pv, self.plotter)
        self.poles = Poles(pv, self.plotter)
        self.objects = Objects(pv, self.plotter)
        self.shadow = Shadow(pv, self.plotter)
        self.markers = PinMarkers(pv, self.plotter) if markers else None
        self.cloth = self.cloth_actor = self.wire = self.wire_actor = None
        self.lines = self.lines_actor = None
        self._model = None
        self._faces_for: tuple[int, int] | None = None  # (stride, torn count) drawn now
        self._tri_constraints: np.ndarray | None = None  # each triangle's edges' constraints
        self._positions: np.ndarray | None = None  # last finite positions drawn
        self._pick_state: tuple | None = None      # (world→clip matrix, positions)
        self._scene = None
        self._appearance_key = None
        self.textures = TextureCache()
        self.camera = OrbitCamera()
        self.update_scene(scene)
        self.reset_camera()

    # -- settings -------------------------------------------------------------------------
    def update_scene(self, scene) -> None:
        """Apply appearance and floor settings; cheap when nothing changed."""
        self._scene = scene
        a, s, c = scene.appearance, scene.scene, scene.cloth
        key = (tuple(vars(a).items()), s.floor, s.floor_height, c.extent(), c.height)
        if key == self._appearance_key:
            return
        self._appearance_key = key
        self.plotter.set_background(a.fog_color)
        self.ground.update(scene, self.textures.image(a.ground_texture))
        self.shadow.update_scene(scene, self.ground.textured)
        if self.cloth_actor is not None:
            self._style_cloth()
        if self.lines_actor is not None:
            self.lines_actor.SetVisibility(bool(a.show_constraints))

    def _style_cloth(self) -> None:
        a = self._scene.appearance
        color = hex_rgb(a.cloth_color)
        image = self.textures.image(a.cloth_texture)
        texture = self.textures.texture(self.pv, image)
        if texture is not None:
            color = np.ones(3) * 0.9  # let the image show its own colours
        for actor in (self.cloth_actor, self.wire_actor):
            actor.texture = texture
            prop = actor.prop
            prop.color = tuple(color)
            prop.ambient = 1.0
            prop.ambient_color = tuple(np.clip(AMBIENT * color, 0, 1))
            prop.diffuse = 0.8
            prop.specular = 1.0
            prop.specular_color = tuple(hex_rgb(a.cloth_specular))
            prop.specular_power = 8.0  # ≈ three.js's Blinn-Phong shininess 30 as Phong
            back = self.pv.Property()  # a fresh copy: the front's settings, a darker colour
            back.DeepCopy(prop)
            back.color = tuple(BACK_SHADE * color)
            back.ambient_color = tuple(np.clip(AMBIENT * BACK_SHADE * color, 0, 1))
            actor.SetBackfaceProperty(back)
        self.cloth_actor.SetVisibility(not a.wireframe)
        self.wire_actor.SetVisibility(bool(a.wireframe))

    # -- the cloth mesh -------------------------------------------------------------------
    def _build_cloth(self, model, positions: np.ndarray) -> None:
        """The sheet as triangles (surface mode) and as its unique edges (wireframe mode),
        plus the constraint lines; all three share one vtkPoints, so a frame updates the
        positions once. Unique edges rather than VTK's wireframe style: that draws every
        shared edge twice and was 2.5x slower for a 128x128 sheet."""
        pv = self.pv
        for actor in (self.cloth_actor, self.wire_actor, self.lines_actor):
            if actor is not None:
                self.plotter.remove_actor(actor, render=False)
        # float32: what the GL buffers hold, so VTK uploads them without converting
        self.cloth = pv.PolyData()  # points alone: PolyData(points) would add a vertex each
        self.cloth.points = positions.astype(np.float32)
        self._model, self._faces_for, self._tri_constraints = model, None, None
        self._wire_for = None  # (WireLook, torn count) the wire's lines are drawn for
        self.cloth.active_texture_coordinates = grid_uv(model.nx, model.nz, model.width,
                                                        model.length)
        self.cloth.point_data["Normals"] = np.zeros(positions.shape, np.float32)  # _update_cloth
        self.cloth.point_data.active_normals_name = "Normals"
        # NumPy views of VTK's own arrays: each frame writes into them, allocating nothing
        self._points_view = self.cloth.points
        self._normals_view = self.cloth.point_data["Normals"]
        self.cloth_actor = self._add_shared(self.cloth)
        self.wire = self._shared_lines()  # its lines and the constraint lines: _set_faces
        self.wire.GetPointData().SetNormals(self.cloth.GetPointData().GetNormals())
        self.wire.GetPointData().SetTCoords(self.cloth.GetPointData().GetTCoords())
        self.wire_actor = self._add_shared(self.wire)
        self.lines = self._shared_lines()
        self._set_lines(np.ones(model.num_constraints, bool))
        self.lines_actor = self.plotter.add_mesh(self.lines, scalars="rgb", rgb=True,
                                                 lighting=False, line_width=1.5,
                                                 show_scalar_bar=False, reset_camera=False)
        self._style_cloth()
        self.lines_actor.SetVisibility(bool(self._scene.appearance.show_constraints))

    def _set_faces(self, snapshot) -> None:
        """The one place the sheet's drawn triangles are chosen: the model's own; at stride > 1
        those of every stride-th row and column (see _detail_stride); on a torn sheet, only
        the triangles whose three constraints all hold, so a tear shows as a gap (drawn at
        stride 1: thinned rows would bridge it). The wireframe draws the edges of the drawn
        triangles at stride 1 that wire.py picks for the picture's size, and the constraint
        lines lose the torn ones. Rebuilt only when the stride, the wires or the torn count
        change; all particles stay in the points (picking and the lines use them)."""
        model, alive = self._model, snapshot.alive
        torn = 0 if alive is None else int(alive.size - np.count_nonzero(alive))
        stride = (1, 1) if torn else self._detail_stride()
        if self._faces_for != (stride, torn):
            self._set_triangles(stride, torn, alive)
        look = self._wire_look() if self._scene.appearance.wireframe else None
        if look is not None and self._wire_for != (look, torn):
            self._wire_for = (look, torn)
            edges = wire_edges(self._edges, model.shape, look)
            self.wire.lines = np.c_[np.full(len(edges), 2, np.int64), edges].ravel()
            self.wire_actor.prop.line_width = look.width

    def _wire_look(self):
        """From the last frame's grid as drawn; before one, the grid seen face-on."""
        gaps = None
        if self._pick_state is not None:
            matrix, positions = self._pick_state
            gaps = grid_gaps_px(matrix, positions, self._model.shape, self.size)
        return wire_look(*(gaps or (self._cell_px(),) * 2))

    def _set_triangles(self, stride: tuple[int, int], torn: int, alive) -> None:
        model = self._model
        torn_changed = self._faces_for is None or self._faces_for[1] != torn
        self._faces_for = (stride, torn)
        if torn:
            if self._tri_constraints is None:
                self._tri_constraints = triangle_constraints(model)
            tri = intact_triangles(model, alive, self._tri_constraints)
        elif stride == (1, 1):
            tri = np.asarray(model.triangles, dtype=np.int64)
        else:
            tri = grid_cell_triangles(model.nx, thinned_rows(model.nz, stride[0]),
                                      thinned_rows(model.nx, stride[1]))
        self.cloth.faces = np.c_[np.full(len(tri), 3, np.int64), tri].ravel()
        self._tri = tri
        if torn_changed:
            whole = tri if stride == (1, 1) else np.asarray(model.triangles, dtype=np.int64)
            self._edges = triangle_edges(whole) if len(whole) else np.zeros((0, 2), np.int64)
            self._wire_for = None
            self._set_lines(alive.astype(bool) if torn else
                            np.ones(model.num_constraints, bool))

    def _set_lines(self, keep: np.ndarray) -> None:
        """The constraint lines (appearance.show_constraints) of the constraints kept."""
        model = self._model
        kept = np.asarray(model.edges, np.int64)[keep]
        self.lines.lines = np.c_[np.full(len(kept), 2, np.int64), kept].ravel()
        self.lines.cell_data["rgb"] = family_colors(np.asarray(model.family)[keep])

    def _detail_stride(self) -> tuple[int, int]:
        """How many grid rows one drawn row spans, and how many columns one drawn column: 1
        unless the sheet's cells would be narrower than MIN_CELL_PX on screen along that
        side (at 640×384 a 128² sheet's are 1.9 px, a 256²'s 0.9 px). Software GL pays per
        triangle, not per pixel, for triangles this small (each is set up and shaded in at
        least one 4×4 block: a 128² sheet's 32k triangles were 60 % of a 640×384 frame);
        what thinning loses, creases a few pixels wide, hardly shows. Each side is thinned
        by its own spacing, so a strip's coarse side is not thinned for its fine one. The
        wireframe is always drawn whole: it shows the mesh itself."""
        m = self._model
        if self._scene.appearance.wireframe:
            return 1, 1
        half_height_m = self.camera.half_height(self.size)
        px_per_m = self.size[1] / (2.0 * half_height_m)
        return tuple(1 if count < 3 else max(1, math.ceil(MIN_CELL_PX / max(h * px_per_m, 1e-9)))
                     for count, h in ((m.nz, m.spacing_z), (m.nx, m.spacing_x)))

    def _cell_px(self) -> float:
        """How wide a grid cell of the sheet is on screen, at the camera's distance."""
        half_height_m = self.camera.half_height(self.size)
        return self._model.spacing * self.size[1] / (2.0 * half_height_m)

    def _shared_lines(self):
        mesh = self.pv.PolyData()
        mesh.SetPoints(self.cloth.GetPoints())
        return mesh

    def _add_shared(self, mesh):
        actor = self.plotter.add_mesh(mesh, scalars=None, reset_camera=False,
                                      show_scalar_bar=False)
        actor.mapper.SetScalarVisibility(False)
        actor.prop.interpolation = "phong"
        return actor

    def _update_cloth(self, positions: np.ndarray) -> None:
        self._points_view[:] = positions
        vertex_normals(positions, self._tri, self._normals_view)
        self.cloth.GetPoints().Modified()
        self._normals_view.VTKObject.Modified()
        for mesh in (self.cloth, self.wire, self.lines):
            mesh.Modified()

    def _good_positions(self, snapshot) -> np.ndarray:
        """The snapshot's positions if all finite (and sane); otherwise the last good ones (or
        the rest shape): NaN or inf must never reach VTK, whose bounds and clipping would go
        wild."""
        x = np.asarray(snapshot.positions, dtype=np.float64)
        n = snapshot.model.num_particles
        if x.shape == (n, 3) and drawable(x, 1e6):
            return x
        if self._positions is not None and len(self._positions) == n:
            return self._positions
        return np.asarray(snapshot.model.rest_positions, dtype=np.float64)

    # -- camera (camera.py) ----------------------------------------------------------------
    def reset_camera(self) -> None:
        self.camera.home(self._scene.cloth, self._scene.scene)
        self._apply_camera()

    def orbit(self, d_azimuth: float, d_elevation: float) -> None:
        self.camera.orbit(d_azimuth, d_elevation)
        self._apply_camera()

    def zoom(self, factor: float) -> None:
        """factor > 1 moves closer."""
        self.camera.zoom(factor)
        self._apply_camera()

    def _apply_camera(self) -> None:
        self.camera.apply(self.plotter.camera, self.size, self._scene.cloth, self._scene.scene)
        self.ground.shade(self.camera.elevation)

    # -- drawing --------------------------------------------------------------------------
    def resize(self, w: int, h: int) -> None:
        size = check_size(w, h)
        if size != self.size:
            self.size = size
            self.plotter.window_size = size

    def render(self, snapshot, auto_rotate_deg: float | None = None) -> np.ndarray:
        """Draw one snapshot; returns the picture as (H, W, 3) uint8. With auto_rotate on,
        the camera first turns `auto_rotate_deg` (default: one frame's worth at 30 fps; the
        app passes an amount by wall-clock time, as its render rate varies)."""
        if snapshot.scene is not self._scene:
            self.update_scene(snapshot.scene)
        positions = self._good_positions(snapshot)
        if snapshot.model is not self._model:
            self._build_cloth(snapshot.model, positions)
        self._set_faces(snapshot)
        self.poles.update(self._scene, snapshot.model)
        self._update_cloth(positions)
        self._positions = positions
        self.objects.update(snapshot.objects)
        if self.markers is not None:
            self.markers.update(snapshot.model, positions, self._scene.appearance.show_pins)
        self.shadow.update(positions, (snapshot.model.nx, snapshot.model.nz),
                           self.camera.elevation,
                           self._tri, self._faces_for[1])
        if self._scene.appearance.auto_rotate:
            step = AUTO_ROTATE_DEG if auto_rotate_deg is None else float(auto_rotate_deg)
            self.camera.azimuth = (self.camera.azimuth + step) % 360.0
        self._apply_camera()
        image = self._grab()
        w, h = self.size
        matrix = self.plotter.camera.GetCompositeProjectionTransformMatrix(w / h, -1, 1)
        m = np.array([[matrix.GetElement(i, j) for j in range(4)] for i in range(4)])
        # one assignment: readers see old or new. Not a copy: a snapshot's positions are its
        # own, never changed after (runner.Snapshot), and so are the rest positions.
        self._pick_state = (m, positions)
        return image

    def _grab(self) -> np.ndarray:
        # The window itself, not plotter.render(): that one skips the first frame until a
        # screenshot has run PyVista's first-render camera reset, which our camera never needs.
        self.plotter.ren_win.Render()
        return antialias_bottom_up(self._read_rgba())

    def _read_rgba(self) -> np.ndarray:
        """The drawn picture as GL holds it: (H, W, 4) uint8, rows from the bottom, in one
        kept vtkUnsignedCharArray (valid until the next render). From the front buffer, as
        plotter.screenshot reads it, but RGBA: Mesa copies that straight out (0.07 ms at
        882×696) where RGB goes through a conversion (0.6 ms)."""
        w, h = self.size
        self.plotter.ren_win.GetRGBACharPixelData(0, 0, w - 1, h - 1, 1, self._pixels, 0)
        return self.pv.convert_array(self._pixels).reshape(h, w, 4)

    def read_pixels(self) -> np.ndarray:
        """The drawn picture, unsmoothed, as an (H, W, 3) uint8 view of a buffer reused every
        frame (valid until the next render); rows from the top. The screenshot's pixels
        (plotter.screenshot builds an image filter and copies and flips them twice)."""
        return self._read_rgba()[::-1, :, :3]

    def pick(self, u: float, v: float) -> int | None:
        """The particle drawn nearest the image point (u, v), both 0..1 from the top-left;
        None when the pointer is not near the sheet. Safe from any thread."""
        state = self._pick_state
        if state is None or not (math.isfinite(u) and math.isfinite(v)):
            return None
        return pick_nearest(state[0], state[1], u, v)

    def screen_delta_to_world(self, particle: int, du: float, dv: float
                              ) -> tuple[float, float, float] | None:
        """The world motion, in the camera's view plane at `particle`'s depth in the last
        frame, that moves its projection by (du, dv) image fractions (v downward). None
        before the first render or for an unknown particle. Safe from any thread."""
        state = self._pick_state
        if state is None:
            return None
        matrix, positions = state
        try:
            k = int(particle)
        except (TypeError, ValueError):
            return None
        if not 0 <= k < len(positions):
            return None
        d = view_plane_delta(matrix, positions[k], float(du), float(dv))
        return None if d is None else (float(d[0]), float(d[1]), float(d[2]))

    def close(self) -> None:
        if self.plotter is not None:
            self.plotter.close()
            self.plotter = None
