"""Kitty graphics protocol: an RGB frame → APC strings (`ESC _ G keys ; base64 ESC \\`).

A frame is sent raw RGB (`f=24`) compressed with zlib (`o=z`; level 1: the cloth's flat
background compresses ~10× at a few ms, PNG would cost a filter pass more), base64-encoded in
chunks of at most 4096 bytes (`m=1` on all but the last) and scaled by the terminal into the
preview's cells (`c`, `r`).

Frames alternate between two image ids: re-sending data under the id on screen blanks it
until decoded (kitty, Ghostty), so the next frame goes to the idle id, is placed (same
placement id, `C=1` keeps the cursor), and only then the other id's image is deleted.
The picture is drawn over text (z=0): under text (z<0), kitty 0.26.5 on Mesa's llvmpipe
tinted and ghosted the rest of the window (seen in screenshots under Xvfb).

Not used: Unicode placeholders (`U=1`, kitty ≥ 0.28 and Ghostty), which would let Textual
clip the picture; the kitty on hand (Debian 12's 0.26.5) has none, so they could not be tried.
"""

from __future__ import annotations

import base64
import zlib

import numpy as np

APC = "\x1b_G"
ST = "\x1b\\"
CHUNK = 4096  # the protocol's maximum base64 bytes per escape
PLACEMENT_ID = 1
COMPRESS_LEVEL = 1



def _escape(keys: dict[str, object], payload: str = "") -> str:
    head = ",".join(f"{k}={v}" for k, v in keys.items())
    return f"{APC}{head};{payload}{ST}" if payload else f"{APC}{head}{ST}"


def transmit(image: np.ndarray, image_id: int, *, keys: dict[str, object] | None = None,
             level: int = COMPRESS_LEVEL) -> str:
    """The (H, W, 3) uint8 image under `image_id`, compressed and chunked; `keys` are added
    to the first chunk (e.g. `a=T` and a placement)."""
    h, w = image.shape[:2]
    raw = np.ascontiguousarray(image[..., :3], dtype=np.uint8).tobytes()
    data = base64.b64encode(zlib.compress(raw, level)).decode("ascii")
    first = {"a": "t", "q": 2, "f": 24, "o": "z", "s": w, "v": h, "i": image_id}
    first.update(keys or {})
    chunks = [data[k:k + CHUNK] for k in range(0, len(data), CHUNK)] or [""]
    out = []
    for n, chunk in enumerate(chunks):
        more = {"m": 1 if n < len(chunks) - 1 else 0}
        head = {**first, **more} if n == 0 else {"q": 2, **more}
        out.append(_escape(head, chunk))
    return "".join(out)


def place(image_id: int, cols: int, rows: int, placement_id: int = PLACEMENT_ID) -> str:
    """Show `image_id` at the cursor scaled into cols × rows cells, replacing this placement
    id's previous picture; the cursor is left where it was (`C=1`)."""
    return _escape({"a": "p", "q": 2, "i": image_id, "p": placement_id, "c": cols, "r": rows,
                    "C": 1})


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


class KittyFrames:
    """Encodes successive frames under two alternating image ids (see the module docstring)."""

    def __init__(self, base_id: int = 0x43_4C):  # "CL"
        self.ids = (base_id, base_id + 1)
        self._next = 0

    def encode(self, image: np.ndarray, cols: int, rows: int) -> str:
        """Transmit under the idle id, place it, delete the shown one: no blank between."""
        new, old = self.ids[self._next], self.ids[1 - self._next]
        self._next = 1 - self._next
        return transmit(image, new) + place(new, cols, rows) + delete_image(old)

    def clear(self) -> str:
        return delete_image(self.ids[0]) + delete_image(self.ids[1])
