"""Anti-aliasing as a compiled pass over the finished picture, in the spirit of FXAA: where
the brightness jumps (an edge), a pixel is blended with its neighbour across the edge by how
much it differs from its surroundings, which softens stair steps and speckle along the
sheet's outline and the poles.

Why not the GL's: measured at 640×384 in Mesa's software GL (docs/rendering.md), VTK's FXAA
pass cost about 12 ms per frame and 4× MSAA about 45 ms, against a frame budget of ~8 ms;
this pass costs about 1 ms at 882×696 (the flip and the read-back copy included) and leaves
flat areas untouched. It is FXAA's sub-pixel part only (no search along long edges), which
is what the half-block preview needs most."""

from __future__ import annotations

import numpy as np

from ..sim.jit import kernel

EDGE_MIN = 8.0     # brightness range (0..255) below which a pixel is left alone
EDGE_SHARE = 0.125  # ... or below this share of the brightest neighbour (FXAA's thresholds)
SUBPIXEL = 0.75     # FXAA's default sub-pixel strength: a lone pixel takes 3/4 of its neighbour


@kernel()
def blend_across_edges(bottom_up, luma, edge, out):
    """`out` (H, W, 3) uint8: the picture `bottom_up` top row first, its edge pixels blended.
    `bottom_up` (H, W, 4) uint8 RGBA, C-ordered, rows from the bottom as GL reads them.
    `luma` (H, W) float32 and `edge` (W,) bool are scratch, C-ordered.

    Rows are read through row views indexed from 0 up: with `luma[y, x - 1]` numba's
    negative-index wrap-around check kept LLVM from vectorizing, and the edge test over
    every pixel (branch-free, so it vectorizes) took 10× as long."""
    h, w = bottom_up.shape[0], bottom_up.shape[1]
    rgb = out.reshape(h, 3 * w)
    for y in range(h):
        src, row, lum = bottom_up[h - 1 - y].ravel(), rgb[y], luma[y]
        for x in range(w):
            r, g, b = src[4 * x], src[4 * x + 1], src[4 * x + 2]
            row[3 * x], row[3 * x + 1], row[3 * x + 2] = r, g, b
            lum[x] = 0.299 * r + 0.587 * g + 0.114 * b
    for y in range(1, h - 1):
        up, mid, down = luma[y - 1], luma[y], luma[y + 1]
        for x in range(w - 2):  # edge[x + 1]: is pixel x + 1 of this row on an edge?
            m, n, s, e, wl = mid[x + 1], up[x + 1], down[x + 1], mid[x + 2], mid[x]
            hi = max(max(max(m, n), max(s, e)), wl)
            span = hi - min(min(min(m, n), min(s, e)), wl)
            edge[x + 1] = (span >= EDGE_MIN) & (span >= EDGE_SHARE * hi)
        for x in range(1, w - 1):
            if not edge[x]:
                continue
            m, n, s, e, wl = mid[x], up[x], down[x], mid[x + 1], mid[x - 1]
            span = max(m, n, s, e, wl) - min(m, n, s, e, wl)
            # FXAA's sub-pixel amount: how far the pixel stands out from its 3×3 surroundings
            # (a lone or corner pixel much, a pixel on a straight edge little)
            around = (2.0 * (n + s + e + wl) + up[x - 1] + up[x + 1]
                      + down[x - 1] + down[x + 1]) / 12.0
            t = min(1.0, abs(around - m) / span)
            t = (3.0 - 2.0 * t) * t * t
            blend = SUBPIXEL * t * t
            if abs(n + s - 2.0 * m) >= abs(e + wl - 2.0 * m):  # the edge runs horizontally
                ty, tx = (y - 1, x) if abs(n - m) >= abs(s - m) else (y + 1, x)
            else:
                ty, tx = (y, x - 1) if abs(wl - m) >= abs(e - m) else (y, x + 1)
            here, there = bottom_up[h - 1 - y, x], bottom_up[h - 1 - ty, tx]
            for c in range(3):
                out[y, x, c] = np.uint8((1.0 - blend) * here[c] + blend * there[c] + 0.5)


def antialias_bottom_up(rgba: np.ndarray) -> np.ndarray:
    """A new (H, W, 3) uint8 picture, top row first, with jagged edges softened, from a GL
    read-back: (H, W, 4) uint8 RGBA, C-ordered, rows from the bottom."""
    h, w = rgba.shape[:2]
    out = np.empty((h, w, 3), np.uint8)
    blend_across_edges(np.ascontiguousarray(rgba, dtype=np.uint8),
                       np.empty((h, w), np.float32), np.zeros(w, np.bool_), out)
    return out


def antialias(image: np.ndarray) -> np.ndarray:
    """A new (H, W, 3) uint8 picture with jagged edges softened; `image` (H, W, 3 or 4)
    uint8, rows from the top, any strides."""
    image = np.asarray(image, dtype=np.uint8)
    rgba = np.zeros(image.shape[:2] + (4,), np.uint8)
    rgba[..., :3] = image[::-1, :, :3]
    return antialias_bottom_up(rgba)
