"""PNG files built chunk by chunk, for tests of what a texture loader meets in the wild:
every colour type and bit depth, animated PNGs, truncated files, and huge images whose
rows are zeros (so a 12000² 1-bit PNG is a few kilobytes)."""

from __future__ import annotations

import struct
import zlib

import numpy as np

SIGNATURE = b"\x89PNG\r\n\x1a\n"
CHANNELS = {0: 1, 2: 3, 3: 1, 4: 2, 6: 4}


def chunk(kind: bytes, data: bytes) -> bytes:
    return struct.pack(">I", len(data)) + kind + data + struct.pack(
        ">I", zlib.crc32(kind + data) & 0xFFFFFFFF)


def ihdr(width: int, height: int, depth: int, colour: int) -> bytes:
    return chunk(b"IHDR", struct.pack(">IIBBBBB", width, height, depth, colour, 0, 0, 0))


def _rows(pixels: np.ndarray, depth: int) -> bytes:
    """Filter type 0 rows of `pixels` (height, width, channels) at `depth` bits."""
    h, w, c = pixels.shape
    if depth == 16:
        body = pixels.astype(">u2").reshape(h, w * c).view(np.uint8).reshape(h, -1)
    elif depth == 8:
        body = pixels.astype(np.uint8).reshape(h, w * c)
    else:  # 1, 2, 4 bits: pack samples big-endian into bytes
        per_byte = 8 // depth
        flat = pixels.reshape(h, w * c).astype(np.uint8)
        pad = (-flat.shape[1]) % per_byte
        flat = np.pad(flat, ((0, 0), (0, pad))).reshape(h, -1, per_byte)
        shifts = depth * np.arange(per_byte - 1, -1, -1, dtype=np.uint8)
        body = np.bitwise_or.reduce(flat << shifts, axis=2).astype(np.uint8)
    return np.hstack([np.zeros((h, 1), np.uint8), body]).tobytes()


def png(pixels: np.ndarray, depth: int = 8, colour: int | None = None,
        palette: np.ndarray | None = None) -> bytes:
    """A PNG of `pixels` (height, width[, channels]); the colour type follows the channels
    (1 grey, 2 grey+alpha, 3 RGB, 4 RGBA) unless given (3 = palette, needs `palette`)."""
    if pixels.ndim == 2:
        pixels = pixels[..., None]
    h, w, c = pixels.shape
    colour = {1: 0, 2: 4, 3: 2, 4: 6}[c] if colour is None else colour
    body = ihdr(w, h, depth, colour)
    if colour == 3:
        body += chunk(b"PLTE", np.asarray(palette, np.uint8).tobytes())
    body += chunk(b"IDAT", zlib.compress(_rows(pixels, depth), 9))
    return SIGNATURE + body + chunk(b"IEND", b"")


def blank_png(width: int, height: int, depth: int = 1, colour: int = 0) -> bytes:
    """An all-zero image of any size, compressed row by row without building it in memory."""
    row = bytes(1 + (width * CHANNELS[colour] * depth + 7) // 8)
    z = zlib.compressobj(9)
    data = b"".join(z.compress(row) for _ in range(height)) + z.flush()
    return SIGNATURE + ihdr(width, height, depth, colour) + chunk(b"IDAT", data) + chunk(
        b"IEND", b"")


def header_only(width: int, height: int, depth: int = 8, colour: int = 2) -> bytes:
    """A PNG that declares its size and holds no pixel data: enough for a header check."""
    return SIGNATURE + ihdr(width, height, depth, colour) + chunk(b"IEND", b"")


def animated_png(frames: list[np.ndarray]) -> bytes:
    """An APNG of RGB uint8 frames of one size; the first frame is also the still image."""
    h, w, _ = frames[0].shape
    out = SIGNATURE + ihdr(w, h, 8, 2) + chunk(b"acTL", struct.pack(">II", len(frames), 0))
    seq = 0
    for i, frame in enumerate(frames):
        out += chunk(b"fcTL", struct.pack(">IIIIIHHBB", seq, w, h, 0, 0, 1, 10, 0, 0))
        seq += 1
        data = zlib.compress(_rows(frame, 8))
        if i == 0:
            out += chunk(b"IDAT", data)
        else:
            out += chunk(b"fdAT", struct.pack(">I", seq) + data)
            seq += 1
    return out + chunk(b"IEND", b"")
