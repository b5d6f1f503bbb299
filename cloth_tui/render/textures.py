"""Procedural textures: the built-in 'maze' (cloth) and 'grass' (ground) images, made here
from a seeded random generator rather than downloaded, and resolution of texture names.

Regenerate the committed PNGs with `python -m cloth_tui.render.textures`.
"""

from __future__ import annotations

from pathlib import Path

import numpy as np

from ..resources import textures_dir
from ..png_header import MAX_TEXTURE_SIDE, PngHeaderError, read_png_header


def maze_image(cells: int = 16, cell_px: int = 8, seed: int = 426) -> np.ndarray:
    """A perfect maze (randomised depth-first search), dark walls on a light floor, RGB uint8.
    The maze tiles: its border is a wall on the top/left only, so copies line up."""
    rng = np.random.default_rng(seed)
    grid = np.zeros((2 * cells, 2 * cells), dtype=bool)  # True = open floor
    seen = np.zeros((cells, cells), dtype=bool)
    stack = [(0, 0)]
    seen[0, 0] = True
    grid[1, 1] = True
    while stack:
        i, j = stack[-1]
        steps = [(di, dj) for di, dj in ((0, 1), (1, 0), (0, -1), (-1, 0))
                 if 0 <= i + di < cells and 0 <= j + dj < cells and not seen[i + di, j + dj]]
        if not steps:
            stack.pop()
            continue
        di, dj = steps[rng.integers(len(steps))]
        ni, nj = i + di, j + dj
        seen[ni, nj] = True
        grid[2 * i + 1 + di, 2 * j + 1 + dj] = True  # knock down the wall between
        grid[2 * ni + 1, 2 * nj + 1] = True
        stack.append((ni, nj))
    px = cell_px // 2
    big = np.repeat(np.repeat(grid, px, axis=0), px, axis=1)
    floor, wall = np.array([236, 228, 210], np.uint8), np.array([40, 44, 60], np.uint8)
    return np.where(big[..., None], floor, wall).astype(np.uint8)


def _tileable_noise(size: int, cells: int, rng: np.random.Generator) -> np.ndarray:
    """Value noise on a `cells`-periodic lattice, smoothly interpolated: tiles seamlessly."""
    lattice = rng.random((cells, cells))
    t = np.arange(size) * cells / size
    i0 = np.floor(t).astype(int)
    f = t - i0
    f = f * f * (3 - 2 * f)  # smoothstep, so the lattice does not show
    i1 = (i0 + 1) % cells
    a = lattice[i0][:, i0] * (1 - f)[None, :] + lattice[i0][:, i1] * f[None, :]
    b = lattice[i1][:, i0] * (1 - f)[None, :] + lattice[i1][:, i1] * f[None, :]
    return a * (1 - f)[:, None] + b * f[:, None]


def grass_image(size: int = 64, seed: int = 7) -> np.ndarray:
    """Green multi-octave noise with a few bright blades, RGB uint8, seamlessly tileable.
    Quantised to a small palette so the PNG stays a few KB."""
    rng = np.random.default_rng(seed)
    v = sum(_tileable_noise(size, c, rng) * w for c, w in ((4, 0.5), (8, 0.3), (32, 0.2)))
    v = (v - v.min()) / (np.ptp(v) + 1e-9)
    blades = rng.random((size, size)) < 0.06
    v = np.clip(v + 0.35 * blades, 0.0, 1.0)
    v = np.round(v * 7) / 7  # 8 shades
    dark, light = np.array([38, 78, 30.0]), np.array([118, 168, 70.0])
    return (dark + v[..., None] * (light - dark)).astype(np.uint8)


GENERATORS = {"maze": maze_image, "grass": grass_image}


def write_builtin(folder: Path | None = None) -> list[Path]:
    import imageio.v3 as iio

    folder = textures_dir() if folder is None else folder
    folder.mkdir(parents=True, exist_ok=True)
    out = []
    for name, make in GENERATORS.items():
        path = folder / f"{name}.png"
        iio.imwrite(path, make(), extension=".png")
        out.append(path)
    return out


class TextureError(ValueError):
    """A texture file that cannot be used. One-line message naming the file."""


def load_texture_image(name: str) -> np.ndarray | None:
    """RGB uint8 image for a texture setting: None for 'none', a built-in by name (made in
    memory if its PNG is missing), or a PNG path. Any PNG colour type and bit depth is
    converted to RGB (alpha dropped); an animated PNG gives its first frame; a side above
    MAX_TEXTURE_SIDE is downscaled. Raises TextureError for a file that is not a readable
    PNG or declares more than png_header.MAX_TEXTURE_PIXELS (checked before decoding)."""
    if name in ("", "none"):
        return None
    if name in GENERATORS:
        path = textures_dir() / f"{name}.png"
        if not path.is_file():
            return GENERATORS[name]()
    else:
        try:
            path = Path(name).expanduser()
        except RuntimeError:  # `~nosuchuser/…`
            raise TextureError(f"texture {name}: no such user's home folder") from None
    try:
        read_png_header(path)
    except PngHeaderError as e:
        raise TextureError(f"texture {path}: {e}") from None
    except OSError as e:
        raise TextureError(f"texture {path}: cannot read: {e.strerror}") from None
    return _decode_rgb(path)


def _decode_rgb(path: Path) -> np.ndarray:
    from PIL import Image

    try:
        with Image.open(path, formats=["PNG"]) as im:
            im.seek(0)  # an animated PNG: its first frame
            im.load()
            if im.mode.startswith("I"):  # 16- or 32-bit grey: scale to 8 bits ourselves
                grey = np.asarray(im).astype(np.float64)
                grey = np.clip(grey * (255.0 / 65535.0), 0, 255).astype(np.uint8)
                rgb = Image.fromarray(grey).convert("RGB")
            else:
                rgb = im.convert("RGB")
        if max(rgb.size) > MAX_TEXTURE_SIDE:
            rgb.thumbnail((MAX_TEXTURE_SIDE, MAX_TEXTURE_SIDE), Image.Resampling.BOX)
        return np.ascontiguousarray(np.asarray(rgb, dtype=np.uint8))
    except Exception as e:  # Pillow reports damaged data as OSError, SyntaxError,
        # ValueError, EOFError or zlib.error, depending on where the damage is
        detail = str(e).splitlines()[0] if str(e) else type(e).__name__
        raise TextureError(f"texture {path}: cannot decode: {detail}") from None


if __name__ == "__main__":
    for p in write_builtin():
        print(f"{p} ({p.stat().st_size} bytes)")


class TextureCache:
    """The renderer's texture images by name, each read once. A texture is decoration: a
    broken one draws untextured, and `notices` says so until the caller takes them."""

    def __init__(self):
        self._images: dict[str, np.ndarray | None] = {}
        self.notices: list[str] = []  # textures drawn without, not yet reported

    def image(self, name: str) -> np.ndarray | None:
        if name not in self._images:
            try:
                self._images[name] = load_texture_image(name)
            except Exception as e:
                self._images[name] = None
                self._failed(e)
        return self._images[name]

    def texture(self, pv, image):
        """A PyVista texture of `image`, None for none (or one VTK refuses)."""
        if image is None:
            return None
        try:
            return pv.Texture(image)
        except Exception as e:
            self._failed(e)
            return None

    def _failed(self, e: Exception) -> None:
        reason = str(e) if isinstance(e, ValueError) else f"texture: {type(e).__name__}: {e}"
        self.notices.append(f"{reason}; drawn without it")
