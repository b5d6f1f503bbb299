"""The size and pixel format of a PNG, from its first 33 bytes, without decoding it.

A texture's size is checked here before any decoder allocates memory for it: a PNG of a few
kilobytes can declare 12000 × 12000 pixels (gigabytes once decoded). Pure Python, so the
scene loader can check texture files without importing an image library.
"""

from __future__ import annotations

import os
import struct
from typing import NamedTuple

PNG_SIGNATURE = b"\x89PNG\r\n\x1a\n"
# Texture files larger than this many pixels are refused unread. 4096 × 4096 decodes to at
# most 64 MB (Pillow keeps 4 bytes per pixel); larger images are downscaled after decoding,
# see render/textures.py.
MAX_TEXTURE_PIXELS = 4096 * 4096
# Decoded textures are downscaled (keeping their aspect) so that neither side exceeds this:
# the preview is a few hundred pixels wide, and GL texture memory is not free.
MAX_TEXTURE_SIDE = 1024
# Allowed bit depths per PNG colour type (PNG specification, table 11.1).
_BIT_DEPTHS = {0: (1, 2, 4, 8, 16), 2: (8, 16), 3: (1, 2, 4, 8), 4: (8, 16), 6: (8, 16)}
COLOUR_TYPE_NAMES = {0: "grey", 2: "RGB", 3: "palette", 4: "grey+alpha", 6: "RGBA"}


class PngHeaderError(ValueError):
    """Not a PNG, a damaged header, or an image too large to read. One-line message."""


class PngHeader(NamedTuple):
    width: int
    height: int
    bit_depth: int
    colour_type: int


def read_png_header(path: str | os.PathLike) -> PngHeader:
    """The header of the PNG at `path`; PngHeaderError when it is not a well-formed PNG
    header or declares more than MAX_TEXTURE_PIXELS. OSError when the file cannot be read."""
    with open(path, "rb") as fh:
        head = fh.read(33)
    if not head.startswith(PNG_SIGNATURE):
        raise PngHeaderError("not a PNG file")
    if len(head) < 33 or head[12:16] != b"IHDR" or struct.unpack(">I", head[8:12])[0] != 13:
        raise PngHeaderError("damaged PNG header")
    width, height, depth, colour, compression, filt, interlace = struct.unpack(
        ">IIBBBBB", head[16:29])
    if (not 0 < width < 2**31 or not 0 < height < 2**31
            or depth not in _BIT_DEPTHS.get(colour, ()) or compression or filt
            or interlace > 1):
        raise PngHeaderError("damaged PNG header")
    if width * height > MAX_TEXTURE_PIXELS:
        raise PngHeaderError(f"the image is {width}×{height} pixels; textures may have at "
                             f"most {MAX_TEXTURE_PIXELS} pixels (4096×4096)")
    return PngHeader(width, height, depth, colour)
