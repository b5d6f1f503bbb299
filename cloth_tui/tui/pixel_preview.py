"""The preview in true pixels (kitty graphics or sixel): the same widget contract as the
half-block `Preview` (its messages, crosshair, pointer), but the picture is written to the
terminal at the widget's top-left cell, after Textual's own output, instead of being drawn
in cells. Textual keeps the cells blank; the encoding runs on its own thread (encoder.py) and
only the newest encoded frame is written, on the UI thread, through Textual's driver so the
bytes stay in order with the screen updates.
"""

from __future__ import annotations

import math

import numpy as np
from rich.segment import Segment
from textual import events
from textual.message import Message
from textual.strip import Strip

from .graphics.detect import Graphics
from .graphics.encoder import Encoded, FrameEncoder, Job, codec_for
from .preview import Preview

MAX_PIXELS = 640 * 480 * 2  # kitty: render at most this many pixels; it scales to the cells
SIXEL_MAX_SIDE = 1000        # xterm's default sixel limit, each side


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
        """An encoded frame is ready to be written (posted from the encoding thread)."""

    def __init__(self, graphics: Graphics, *, id: str | None = None) -> None:
        super().__init__(id=id)
        self.graphics = graphics
        self.encoder = FrameEncoder(codec_for(graphics.mode), self._on_encoded)
        self._encoded_box: Encoded | None = None
        self._painted_posted = False
        self._shown_on_terminal = False
        self.frames_written = 0
        self.last_encode_ms = 0.0

    def on_mount(self) -> None:  # Preview.on_mount runs after this one (Textual walks the MRO)
        self.encoder.start()
        self.app.screen_change_signal.subscribe(self, self._on_screen_change)

    def _on_screen_change(self, screen) -> None:
        """A screen over the preview (help, command palette): take the picture away, as it
        is drawn over text; back on the preview's screen: draw the last frame again (a
        paused simulation sends no new one)."""
        if screen is not self.screen:
            if self._shown_on_terminal:
                self._write(self.encoder.codec.clear())
                self._shown_on_terminal = False
        else:
            self._rebuild()

    def on_unmount(self) -> None:
        self.encoder.stop()
        self._write(self.encoder.codec.clear())

    # -- data in (UI thread) ----------------------------------------------------------------
    def show_image(self, image: np.ndarray) -> None:
        first = self._image is None
        self._image = image
        self.frames_shown += 1
        self._rebuild()
        if first:
            self.refresh()  # the placeholder text goes

    def _rebuild(self) -> None:
        job = self._job()
        if job is not None:
            self.encoder.offer(job)

    def _job(self) -> Job | None:
        """The newest image for the encoder, cut above any notice over the preview: the
        picture is drawn over text, and would hide it."""
        cols, rows = self.size.width, self.size.height
        if self._image is None or cols <= 0 or rows <= 0:
            return None
        shown = rows
        me = self.region
        for toast in self.screen.query("Toast"):
            if toast.region.overlaps(me):
                shown = min(shown, toast.region.y - me.y)
        if shown <= 0:
            return None
        image = self._image
        u, v = self.crosshair
        if shown < rows:
            image = image[:max(1, image.shape[0] * shown // rows)]
            v = v * rows / shown
        return Job(image, cols, shown, (u, v) if self.show_crosshair else None)

    # -- encoded frames (posted from the encoding thread) -----------------------------------
    def _on_encoded(self, encoded: Encoded) -> None:
        self._encoded_box = encoded
        if not self._painted_posted:
            self._painted_posted = True
            self.post_message(self.Painted())

    def on_pixel_preview_painted(self, message: "PixelPreview.Painted") -> None:
        message.stop()
        self._painted_posted = False
        encoded, self._encoded_box = self._encoded_box, None
        if encoded is None:
            return
        if self.screen is not self.app.screen or not self.display:
            if self._shown_on_terminal:  # a screen over the preview: no picture on top
                self._write(self.encoder.codec.clear())
                self._shown_on_terminal = False
            return
        region = self.content_region
        if encoded.cols != region.width or encoded.rows > region.height:
            return  # made for a size the preview no longer has: the next one fits
        # Save the cursor, go to the top-left cell, draw, restore: Textual's idea of the
        # cursor stays right.
        self._write(f"\x1b7\x1b[{region.y + 1};{region.x + 1}H{encoded.data}\x1b8")
        self._shown_on_terminal = True
        self.frames_written += 1
        self.last_encode_ms = encoded.encode_ms

    def _write(self, data: str) -> None:
        # Textual's driver queues its writes on one thread; writing there keeps the picture
        # in order with the screen updates (a direct write could split one of them).
        driver = self.app._driver
        if data and driver is not None:
            driver.write(data)

    # -- Line API: blank cells under the picture --------------------------------------------
    def render_line(self, y: int) -> Strip:
        if self._image is None:
            return super().render_line(y)
        return Strip([Segment(" " * self.size.width)], self.size.width)

    def on_resize(self, event: events.Resize) -> None:
        event.prevent_default()  # not Preview's: it asks for half-block sizes
        cols, rows = event.size.width, event.size.height
        if cols > 0 and rows > 0:
            self.post_message(self.Resized(*render_size(cols, rows, self.graphics.cell_px,
                                                        self.graphics.mode)))
            self._rebuild()
