"""The preview in true pixels (kitty graphics or sixel): the same widget contract as the
half-block `Preview` (its messages, crosshair, pointer), but the picture is written to the
terminal over the widget's cells, after Textual's own output, instead of being drawn in
cells. Textual keeps the cells blank, in the scene's background colour (where a picture does
not reach, the terminal's own background would show). The encoding runs on its own thread
(encoder.py) and only the newest encoded frame is written, on the UI thread, through
Textual's driver so the bytes stay in order with the screen updates.

The picture goes only where no other widget covers the preview (a drawer, a notice, a
tooltip): the covered cells are found in Textual's compositor map, at each frame and at each
layout change, when the picture on screen is moved out of the way at once (kitty) and frames
cut for the old layout are dropped (graphics/layout.py).
"""

from __future__ import annotations

import math

import numpy as np
from rich.color import Color, ColorParseError
from rich.console import COLOR_SYSTEMS
from rich.segment import Segment
from rich.style import Style
from textual import events
from textual.message import Message
from textual.strip import Strip

from ..newest_slot import NewestSlot
from .graphics.detect import Graphics
from .graphics.encoder import Encoded, FrameEncoder, Job, codec_for
from .graphics.layout import Layout, Rect, uncovered_rects
from .preview import Preview
from .textual_adapter import driver_of, widgets_painted_over

MAX_PIXELS = 640 * 480 * 2  # kitty: render at most this many pixels; it scales to the cells
SIXEL_MAX_SIDE = 1000        # xterm's default sixel limit, each side
DEFAULT_FILL = "#000000"     # the blank cells' colour when the scene's cannot be read


def render_size(cols: int, rows: int, cell_px: tuple[int, int], mode: str) -> tuple[int, int]:
    """Pixels to render for cols × rows cells: the cells' real pixel size; for kitty scaled
    down (keeping the shape) to at most MAX_PIXELS, for sixel, which is shown unscaled and
    so must fill the cells itself, only to SIXEL_MAX_SIDE a side. Even sides."""
    w, h = cols * cell_px[0], rows * cell_px[1]
    if mode == "sixel":
        scale = min(1.0, SIXEL_MAX_SIDE / max(w, h, 1))
    else:
        scale = min(1.0, math.sqrt(MAX_PIXELS / max(w * h, 1)))
    return max(2, int(w * scale) // 2 * 2), max(2, int(h * scale) // 2 * 2)


class PixelPreview(Preview):
    class Painted(Message):
        """Posted when an encoded frame is ready to be written (from the encoding thread)."""

    def __init__(self, graphics: Graphics, *, id: str | None = None) -> None:
        super().__init__(id=id)
        self.graphics = graphics
        self.encoder = FrameEncoder(codec_for(graphics.mode), self._on_encoded)
        self._encoded: NewestSlot[Encoded] = NewestSlot()  # from the encoding thread
        self._shown_on_terminal = False
        self._layout_now: Layout | None = None  # the layout the picture on screen is in
        self._fill = DEFAULT_FILL
        self._fill_style = Style(bgcolor=DEFAULT_FILL)
        self._fill_sgr = ""
        self.frames_written = 0
        self.last_encode_ms = 0.0

    def on_mount(self) -> None:  # Preview.on_mount runs after this one (Textual walks the MRO)
        self.encoder.start()
        self.app.screen_change_signal.subscribe(self, self._on_screen_change)
        self.screen.screen_layout_refresh_signal.subscribe(self, self._on_layout_refresh)
        self._update_fill()

    def _on_screen_change(self, screen) -> None:
        """A screen over the preview (help, command palette): take the picture away, as it
        is drawn over text; back on the preview's screen: draw the last frame again (a
        paused simulation sends no new one)."""
        if screen is not self.screen:
            if self._shown_on_terminal:
                self._write(self.encoder.codec.clear())
                self._shown_on_terminal = False
            self._layout_now = None
        else:
            self._rebuild()

    def _on_layout_refresh(self, screen) -> None:
        """Something on the screen moved, appeared or went (Textual has drawn it already):
        the picture leaves what now covers the preview before any other frame comes, and
        the last frame is cut again for the new layout."""
        if screen is not self.screen or self.app.screen is not self.screen:
            return
        layout = self.layout()
        if layout == self._layout_now:
            return
        self._set_layout(layout)
        if self._shown_on_terminal and layout is not None:
            self._write_at_cursor(self.encoder.codec.relayout(layout))
        self._rebuild()

    def on_unmount(self) -> None:
        self.encoder.stop()
        self._write(self.encoder.codec.clear())

    # -- where the picture goes -------------------------------------------------------------
    def layout(self) -> Layout | None:
        """The preview's cells and the parts of them no other widget covers; None when the
        preview is not on the screen."""
        region = self.content_region
        if region.width <= 0 or region.height <= 0 or not self.display:
            return None
        covers: list[Rect] = []
        # Topmost first (Textual's compositor map; no public way to ask what is painted over
        # a widget): every visible widget before the preview is drawn over it.
        for widget, where, clip in widgets_painted_over(self.screen):
            if widget is self:
                break
            if not widget.visible:
                continue  # e.g. the notices' rack: only its toasts are drawn
            part = where.intersection(clip).intersection(region)
            if part.area:
                covers.append((part.x - region.x, part.y - region.y, part.width, part.height))
        else:
            return None  # the preview itself is not drawn
        cols, rows = region.width, region.height
        return Layout((region.x, region.y), cols, rows, uncovered_rects(cols, rows, covers),
                      self.graphics.cell_px,
                      render_size(cols, rows, self.graphics.cell_px, self.graphics.mode),
                      self._fill_sgr)

    def _update_fill(self) -> None:
        """The blank cells take the scene's background colour (the renderer's fog)."""
        scene = getattr(self.app, "scene", None)
        fill = getattr(getattr(scene, "appearance", None), "fog_color", DEFAULT_FILL)
        if fill == self._fill and self._fill_sgr:
            return
        try:
            color = Color.parse(fill)
        except ColorParseError:
            fill, color = DEFAULT_FILL, Color.parse(DEFAULT_FILL)
        self._fill, self._fill_style = fill, Style(bgcolor=color)
        system = COLOR_SYSTEMS.get(self.app.console.color_system or "truecolor")
        self._fill_sgr = ";".join(color.downgrade(system).get_ansi_codes(foreground=False))
        self.refresh()

    # -- data in (UI thread) ----------------------------------------------------------------
    def show_image(self, image: np.ndarray) -> None:
        first = self._image is None
        self._image = image
        self.frames_shown += 1
        self._update_fill()
        self._rebuild()
        if first:
            self.refresh()  # the placeholder text goes

    def _rebuild(self) -> None:
        job = self._job()
        if job is not None:
            self.encoder.offer(job)

    def _job(self) -> Job | None:
        """The newest image for the encoder, with the layout it is to be cut for."""
        layout = self.layout()
        if self._image is None or layout is None or not layout.rects:
            return None
        return Job(self._image, layout, self.crosshair if self.show_crosshair else None)

    # -- encoded frames (posted from the encoding thread) -----------------------------------
    def _on_encoded(self, encoded: Encoded) -> None:
        if self._encoded.put(encoded):
            self.post_message(self.Painted())

    def on_pixel_preview_painted(self, message: "PixelPreview.Painted") -> None:
        message.stop()
        encoded = self._encoded.take()
        if encoded is None:
            return
        codec = self.encoder.codec
        if self.screen is not self.app.screen or not self.display:
            if self._shown_on_terminal:  # a screen over the preview: no picture on top
                self._write(codec.clear())
                self._shown_on_terminal = False
            return
        layout = self.layout()
        if layout is None:
            return
        self._set_layout(layout)
        data = codec.show(encoded.frame, layout)
        if data is None:  # cut for a layout the preview no longer has
            self._rebuild()
            return
        self._write_at_cursor(data)
        self._shown_on_terminal = True
        self.frames_written += 1
        self.last_encode_ms = encoded.encode_ms

    def _set_layout(self, layout: Layout | None) -> None:
        """The layout the picture is now in, noted in the debug log when it changes (where
        a real terminal shows something wrong, this says where the preview drew)."""
        if layout != self._layout_now and layout is not None:
            rects = " ".join(":".join(map(str, r)) for r in layout.rects)
            self._debug_line(f"layout at {layout.origin[0]},{layout.origin[1]} cells "
                             f"{layout.cols}x{layout.rows} picture {layout.picture_px[0]}x"
                             f"{layout.picture_px[1]} free {rects}")
        self._layout_now = layout

    def _debug_line(self, text: str) -> None:
        log = getattr(self.app, "debug_line", None)  # the app's debug log (ClothApp)
        if log is not None:
            log(text)

    def _write_at_cursor(self, data: str) -> None:
        """Bytes that move the cursor, between a save and a restore of it (and of the colours):
        Textual's idea of the cursor stays right."""
        if data:
            self._write(f"\x1b7{data}\x1b8")

    def _write(self, data: str) -> None:
        # Textual's driver queues its writes on one thread; writing there keeps the picture
        # in order with the screen updates (a direct write could split one of them).
        driver = driver_of(self.app)
        if data and driver is not None:
            driver.write(data)

    # -- Line API: blank cells under the picture --------------------------------------------
    def render_line(self, y: int) -> Strip:
        if self._image is None:
            return super().render_line(y)
        return Strip([Segment(" " * self.size.width, self._fill_style)], self.size.width)

    def on_resize(self, event: events.Resize) -> None:
        event.prevent_default()  # not Preview's: it asks for half-block sizes
        cols, rows = event.size.width, event.size.height
        if cols > 0 and rows > 0:
            self.post_message(self.Resized(*render_size(cols, rows, self.graphics.cell_px,
                                                        self.graphics.mode)))
            self._rebuild()
