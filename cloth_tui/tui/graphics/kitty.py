"""Kitty graphics protocol: an RGB frame → APC strings (`ESC _ G keys ; base64 ESC \\`).

A frame is sent raw RGB (`f=24`) compressed with zlib (`o=z`; level 1: the cloth's flat
background compresses ~10× at a few ms, PNG would cost a filter pass more), base64-encoded in
chunks of at most 4096 bytes (`m=1` on all but the last) and scaled by the terminal into the
preview's cells (`c`, `r`).

Frames alternate between two image ids: re-sending data under the id on screen blanks it
until decoded (kitty, Ghostty), so the next frame goes to the idle id, is placed (`C=1` keeps
the cursor), and only then the other id's image is deleted. A picture partly covered by the
app's own widgets (a drawer, a notice) is shown as several placements of the one image, each
a source rectangle of it scaled into an uncovered rectangle of cells (layout.py); when only
the layout changes, the image on screen is placed anew without sending it again.
The picture is drawn over text (z=0): under text (z<0), kitty 0.26.5 on Mesa's llvmpipe
tinted and ghosted the rest of the window (seen in screenshots under Xvfb).

Not used: Unicode placeholders (`U=1`, kitty ≥ 0.28 and Ghostty), which would let Textual
clip the picture; the kitty on hand (Debian 12's 0.26.5) has none, so they could not be tried.
"""

from __future__ import annotations

import base64
import zlib
from dataclasses import dataclass

import numpy as np

from .layout import Layout, Rect, goto

APC = "\x1b_G"
ST = "\x1b\\"
CHUNK = 4096  # the protocol's maximum base64 bytes per escape
PLACEMENT_ID = 1
COMPRESS_LEVEL = 1


def _escape(keys: dict[str, object], payload: str = "") -> str:
    head = ",".join(f"{k}={v}" for k, v in keys.items())
    return f"{APC}{head};{payload}{ST}" if payload else f"{APC}{head}{ST}"


def compress(image: np.ndarray, level: int = COMPRESS_LEVEL) -> str:
    """The (H, W, 3) uint8 image as zlib-compressed raw RGB in base64 (the costly part)."""
    raw = np.ascontiguousarray(image[..., :3], dtype=np.uint8).tobytes()
    return base64.b64encode(zlib.compress(raw, level)).decode("ascii")


def transmit(image: np.ndarray, image_id: int, *, keys: dict[str, object] | None = None,
             level: int = COMPRESS_LEVEL) -> str:
    """The (H, W, 3) uint8 image under `image_id`, compressed and chunked; `keys` are added
    to the first chunk (e.g. `a=T` and a placement)."""
    h, w = image.shape[:2]
    return transmit_compressed(compress(image, level), w, h, image_id, keys=keys)


def transmit_compressed(data: str, width: int, height: int, image_id: int, *,
                        keys: dict[str, object] | None = None) -> str:
    """Already compressed data (`compress`) under `image_id`, in chunks of at most CHUNK."""
    first = {"a": "t", "q": 2, "f": 24, "o": "z", "s": width, "v": height, "i": image_id}
    first.update(keys or {})
    chunks = [data[k:k + CHUNK] for k in range(0, len(data), CHUNK)] or [""]
    out = []
    for n, chunk in enumerate(chunks):
        more = {"m": 1 if n < len(chunks) - 1 else 0}
        head = {**first, **more} if n == 0 else {"q": 2, **more}
        out.append(_escape(head, chunk))
    return "".join(out)


def place(image_id: int, cols: int, rows: int, placement_id: int = PLACEMENT_ID,
          source: tuple[int, int, int, int] | None = None) -> str:
    """Show `image_id` at the cursor scaled into cols × rows cells, replacing this placement
    id's previous picture; the cursor is left where it was (`C=1`). `source`: only this
    (x, y, width, height) rectangle of the image's pixels."""
    keys: dict[str, object] = {"a": "p", "q": 2, "i": image_id, "p": placement_id}
    if source is not None:
        keys.update(zip("xywh", source))
    keys.update({"c": cols, "r": rows, "C": 1})
    return _escape(keys)


def delete_placement(image_id: int, placement_id: int) -> str:
    """Take one placement of the image off the screen; the image's data stays."""
    return _escape({"a": "d", "q": 2, "d": "i", "i": image_id, "p": placement_id})


def delete_image(image_id: int) -> str:
    """Delete the image's placements and free its data (upper-case `I`)."""
    return _escape({"a": "d", "q": 2, "d": "I", "i": image_id})


def delete_all() -> str:
    """Delete every placement and free the data of every image (on leaving the app)."""
    return _escape({"a": "d", "q": 2, "d": "A"})


def query(image_id: int) -> str:
    """A support query: a 1×1 RGB image kitty checks and answers `i=ID;OK` without storing."""
    return _escape({"a": "q", "i": image_id, "s": 1, "v": 1, "t": "d", "f": 24},
                   base64.b64encode(b"\0\0\0").decode("ascii"))


def source_rect(rect: Rect, cols: int, rows: int, width: int, height: int
                ) -> tuple[int, int, int, int]:
    """The pixels of a width × height image, spread over cols × rows cells, that fall in a
    rectangle of those cells; never empty (kitty reads a zero size as "all")."""
    x, y, w, h = rect
    x0, x1 = x * width // cols, (x + w) * width // cols
    y0, y1 = y * height // rows, (y + h) * height // rows
    x0, y0 = min(x0, width - 1), min(y0, height - 1)
    return x0, y0, max(x1 - x0, 1), max(y1 - y0, 1)


@dataclass(frozen=True)
class Compressed:
    """A frame ready to send: its pixels compressed, under no image id yet."""
    data: str
    width: int
    height: int


class KittyFrames:
    """Shows successive frames under two alternating image ids (see the module docstring).
    `prepare` runs on the encoding thread and touches no state; `show`, `relayout` and
    `clear` run on the UI thread in the order their output is written, so they alone decide
    which id is on screen."""

    def __init__(self, base_id: int = 0x43_4C):  # "CL"
        self.ids = (base_id, base_id + 1)
        self._shown: int | None = None            # the id on screen
        self._size = (0, 0)                       # its pixels (width, height)
        self._placements = 0                      # placement ids 1..n in use on it

    def prepare(self, image: np.ndarray, layout: Layout) -> Compressed:
        h, w = image.shape[:2]
        return Compressed(compress(image), w, h)

    def show(self, frame: Compressed, layout: Layout) -> str:
        """Transmit under the idle id, place it in the layout's rectangles, then delete the
        shown one: no blank between."""
        old = self._shown
        new = self.ids[1] if old == self.ids[0] else self.ids[0]
        out = [transmit_compressed(frame.data, frame.width, frame.height, new)]
        self._shown, self._size, self._placements = new, (frame.width, frame.height), 0
        out.append(self._place(layout))
        if old is not None:
            out.append(delete_image(old))
        return "".join(out)

    def relayout(self, layout: Layout) -> str:
        """The image on screen moved into the layout's rectangles (and off the others)."""
        return self._place(layout) if self._shown is not None else ""

    def _place(self, layout: Layout) -> str:
        image_id, (w, h) = self._shown, self._size
        out = []
        for n, rect in enumerate(layout.rects, start=1):
            source = source_rect(rect, layout.cols, layout.rows, w, h)
            out.append(goto(layout, rect) + place(image_id, rect[2], rect[3], n, source))
        for n in range(len(layout.rects) + 1, self._placements + 1):
            out.append(delete_placement(image_id, n))
        self._placements = len(layout.rects)
        return "".join(out)

    def clear(self) -> str:
        self._shown, self._placements = None, 0
        return delete_image(self.ids[0]) + delete_image(self.ids[1])
