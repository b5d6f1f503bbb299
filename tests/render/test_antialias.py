"""The compiled anti-aliasing pass against a plain, slow statement of the same rule."""

import numpy as np

from cloth_tui.render.antialias import EDGE_MIN, EDGE_SHARE, SUBPIXEL, antialias


def reference(image: np.ndarray) -> np.ndarray:
    """FXAA's sub-pixel blend pixel by pixel, in Python, with the kernel's float32 luma."""
    src = image.astype(np.float64)
    luma = (0.299 * src[..., 0] + 0.587 * src[..., 1] + 0.114 * src[..., 2]).astype(np.float32)
    luma = luma.astype(np.float64)
    out = image.copy()
    h, w = luma.shape
    for y in range(1, h - 1):
        for x in range(1, w - 1):
            m, n, s = luma[y, x], luma[y - 1, x], luma[y + 1, x]
            e, wl = luma[y, x + 1], luma[y, x - 1]
            hi, lo = max(m, n, s, e, wl), min(m, n, s, e, wl)
            if hi - lo < EDGE_MIN or hi - lo < EDGE_SHARE * hi:
                continue
            corners = luma[y - 1, x - 1] + luma[y - 1, x + 1] + luma[y + 1, x - 1] \
                + luma[y + 1, x + 1]
            t = min(1.0, abs((2 * (n + s + e + wl) + corners) / 12 - m) / (hi - lo))
            blend = SUBPIXEL * ((3 - 2 * t) * t * t) ** 2
            if abs(n + s - 2 * m) >= abs(e + wl - 2 * m):
                ty, tx = (y - 1, x) if abs(n - m) >= abs(s - m) else (y + 1, x)
            else:
                ty, tx = (y, x - 1) if abs(wl - m) >= abs(e - m) else (y, x + 1)
            out[y, x] = ((1 - blend) * src[y, x] + blend * src[ty, tx] + 0.5).astype(np.uint8)
    return out


def test_the_compiled_pass_blends_exactly_as_the_rule_says():
    rng = np.random.default_rng(7)
    picture = np.full((37, 53, 3), 60, np.uint8)
    picture[5:30, 8:40] = (200, 40, 40)             # a block: straight edges and corners
    picture[12, 20:24] = 255                         # a thin line and lone pixels
    picture[20:34, 30:50] = rng.integers(0, 256, (14, 20, 3), dtype=np.uint8)  # speckle
    for image in (picture, picture[::-1], picture[:, ::-1]):  # flipped views too
        got = antialias(image)
        assert np.abs(got.astype(int) - reference(image).astype(int)).max() <= 1  # rounding
        assert (got != image).any()
