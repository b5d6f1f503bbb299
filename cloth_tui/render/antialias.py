"""Anti-aliasing as a compiled pass over the finished picture, in the spirit of FXAA: where
the brightness jumps (an edge), a pixel is blended with its neighbour across the edge by how
much it differs from its surroundings, which softens stair steps and speckle along the
sheet's outline and the poles.

Why not the GL's: measured at 640×384 in Mesa's software GL (docs/rendering.md), VTK's FXAA
pass cost about 12 ms per frame and 4× MSAA about 45 ms, against a frame budget of ~8 ms;
this pass costs about 1 ms and leaves flat areas untouched. It is FXAA's sub-pixel
part only (no search along long edges), which is what the half-block preview needs most."""

from __future__ import annotations

import numpy as np

from ..sim.jit import kernel

EDGE_MIN = 8.0     # brightness range (0..255) below which a pixel is left alone
EDGE_SHARE = 0.125  # ... or below this share of the brightest neighbour (FXAA's thresholds)
SUBPIXEL = 0.75     # FXAA's default sub-pixel strength: a lone pixel takes 3/4 of its neighbour


@kernel()
def blend_across_edges(src, luma, out):
    """Blend `out`'s edge pixels, `out` holding a copy of `src` (both (H, W, 3) uint8) on
    entry (NumPy copies it 20× faster than a loop here). `luma` (H, W) float32 is scratch."""
    h, w = src.shape[0], src.shape[1]
    for y in range(h):
        for x in range(w):
            luma[y, x] = 0.299 * src[y, x, 0] + 0.587 * src[y, x, 1] + 0.114 * src[y, x, 2]
    for y in range(1, h - 1):
        for x in range(1, w - 1):
            m = luma[y, x]
            n = luma[y - 1, x]
            s = luma[y + 1, x]
            e = luma[y, x + 1]
            wl = luma[y, x - 1]
            hi = max(m, n, s, e, wl)
            lo = min(m, n, s, e, wl)
            span = hi - lo
            if span < EDGE_MIN or span < EDGE_SHARE * hi:
                continue
            # FXAA's sub-pixel amount: how far the pixel stands out from its 3×3 surroundings
            # (a lone or corner pixel much, a pixel on a straight edge little)
            around = (2.0 * (n + s + e + wl) + luma[y - 1, x - 1] + luma[y - 1, x + 1]
                      + luma[y + 1, x - 1] + luma[y + 1, x + 1]) / 12.0
            t = min(1.0, abs(around - m) / span)
            t = (3.0 - 2.0 * t) * t * t
            blend = SUBPIXEL * t * t
            if abs(n + s - 2.0 * m) >= abs(e + wl - 2.0 * m):  # the edge runs horizontally
                ty, tx = (y - 1, x) if abs(n - m) >= abs(s - m) else (y + 1, x)
            else:
                ty, tx = (y, x - 1) if abs(wl - m) >= abs(e - m) else (y, x + 1)
            for c in range(3):
                v = (1.0 - blend) * src[y, x, c] + blend * src[ty, tx, c]
                out[y, x, c] = np.uint8(v + 0.5)


def antialias(image: np.ndarray) -> np.ndarray:
    """A new (H, W, 3) uint8 picture with jagged edges softened."""
    # any strides (a bottom-up read-back viewed top-down is read in place, not copied)
    src = np.asarray(image, dtype=np.uint8)
    out = np.array(src, order="C")
    blend_across_edges(src, np.empty(src.shape[:2], np.float32), out)
    return out
