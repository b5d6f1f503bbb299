"""The live preview: the renderer's image drawn with half-block cells ("▀", top pixel in the
foreground colour, bottom pixel in the background colour), through Textual's Line API.

The conversion is NumPy all the way to the row level: the image is resampled to
(2·rows, cols) by index arrays, colours are packed into integers, and each row becomes one
Segment per run of equal cells, with Rich styles cached by packed colour pair.
"""

from __future__ import annotations

import textwrap
from typing import Any, Callable, Sequence

import numpy as np
from rich.color import Color, ColorSystem
from rich.console import COLOR_SYSTEMS
from rich.segment import Segment
from rich.style import Style
from textual import events
from textual.filter import ANSIToTruecolor, LineFilter
from textual.geometry import Size
from textual.message import Message
from textual.strip import Strip
from textual.widget import Widget

from .graphics.palette import dither_rgb, palette_for

HALF = "▀"
SCALE = 2  # the renderer draws SCALE× the half-block pixels; cells show their average
CROSSHAIR = "╋"
_QUANT = 0xFC  # drop the two low bits of each channel: more shared styles, longer runs


class RecentCache:
    """A memo of `make(key)` bounded in two generations: entries go into the new one; when
    it holds `limit` it becomes the old one (the previous old one is dropped) and entries
    used again move back. What a frame uses stays; what the view no longer shows goes."""

    def __init__(self, make: Callable[[int], Any], limit: int):
        self._make = make
        self._limit = limit
        self._new: dict[int, Any] = {}
        self._old: dict[int, Any] = {}

    def __call__(self, key: int) -> Any:
        value = self._new.get(key)
        if value is None:
            value = self._old.pop(key, None)
            if value is None:
                value = self._make(key)
            if len(self._new) >= self._limit:
                self._old, self._new = self._new, {}
            self._new[key] = value
        return value

    def __len__(self) -> int:
        return len(self._new) + len(self._old)


def _rgb_color(rgb: int) -> Color:
    return Color.from_rgb(rgb >> 16, (rgb >> 8) & 255, rgb & 255)


class StyleCache:
    """Rich styles for packed (top, bottom) colour pairs, sharing their colours. A frame of
    the default scene uses ~450 pairs, but turning the camera keeps making new ones (100–250
    a second), so the cache is bounded (at most 2·`limit` styles and colours, ≤ 7 MB)
    rather than let grow: cleared only at 50,000 styles, with two colours each, it grew the
    app by up to ~30 MB.

    Given the terminal's `color_system`, each new style gets its terminal codes made once
    (Rich keeps them on the style, and Textual draws a style with those when present);
    otherwise Textual makes them through its class-wide cache of 16,384 styles
    (`Strip.render_ansi`), which would then keep every pair the view ever showed alive."""

    def __init__(self, limit: int = 4096, color_system: ColorSystem | None = None):
        colors = RecentCache(_rgb_color, limit)

        def style(key: int) -> Style:
            s = Style(color=colors(key >> 24), bgcolor=colors(key & 0xFFFFFF))
            if color_system is not None:
                s.render(HALF, color_system=color_system)  # Rich keeps the codes on `s`
            return s

        self._styles = RecentCache(style, limit)

    def __call__(self, key: int) -> Style:
        return self._styles(key)

    def __len__(self) -> int:
        return len(self._styles)


def resample(image: np.ndarray, cols: int, rows: int) -> np.ndarray:
    """Nearest-neighbour resample of an (H, W, 3) image to (2·rows, cols, 3)."""
    h, w = image.shape[:2]
    if h % (2 * rows) == 0 and w % cols == 0 and (h > 2 * rows or w > cols):
        # an exact multiple (the preview asks for SCALE× pixels): average, anti-aliased
        # (one strided add per box offset: NumPy's sum over two axes of a 5-d view took
        # 1.6 ms a frame of the UI thread at 228×180, this 0.15)
        ky, kx = h // (2 * rows), w // cols
        total = np.zeros((2 * rows, cols, 3), np.uint16)
        for dy in range(ky):
            for dx in range(kx):
                total += image[dy::ky, dx::kx, :3]
        return (total // (ky * kx)).astype(np.uint8)
    ys = ((np.arange(2 * rows) + 0.5) * (h / (2 * rows))).astype(np.intp)
    xs = ((np.arange(cols) + 0.5) * (w / cols)).astype(np.intp)
    return image[ys[:, None], xs[None, :], :3]


class RowCache:
    """The last frame's strips with their rows' colour keys. A row whose cells did not
    change keeps its Strip, so neither its segments nor Textual's filtered copy of it (kept
    on the Strip) are made again: ~40 % of the rows of a 256² frame (sky, floor), where
    making strips was the UI thread's largest cost."""

    def __init__(self) -> None:
        self.keys: np.ndarray | None = None
        self.strips: list[Strip] = []


def image_to_strips(image: np.ndarray, cols: int, rows: int, styles: StyleCache,
                    crosshair: tuple[int, int] | None = None,
                    palette: np.ndarray | None = None,
                    cache: RowCache | None = None) -> list[Strip]:
    """One Strip per terminal row of `cols` half-block cells showing `image`; below
    truecolor, dithered to the terminal's `palette` (else the terminal's downgrade to the
    nearest colour turns the shading into flat blocks). With `cache`, rows unchanged since
    the call that filled it keep their Strip."""
    if cols <= 0 or rows <= 0:
        return []
    px = resample(image, cols, rows)
    px = dither_rgb(px, palette).astype(np.uint32) if palette is not None else (
        px.astype(np.uint32) & _QUANT)
    packed = (px[..., 0] << 16) | (px[..., 1] << 8) | px[..., 2]
    keys = (packed[0::2].astype(np.int64) << 24) | packed[1::2].astype(np.int64)
    change = keys[:, 1:] != keys[:, :-1]
    same = np.zeros(rows, bool)
    if cache is not None and cache.keys is not None and cache.keys.shape == keys.shape:
        same = (cache.keys == keys).all(axis=1)
    strips = []
    for r in range(rows):
        if same[r]:
            strips.append(cache.strips[r])
            continue
        row = keys[r]
        starts = np.concatenate(([0], np.flatnonzero(change[r]) + 1)).tolist()
        ends = starts[1:] + [cols]
        vals = row[starts].tolist()
        segs = [Segment(HALF * (e - s), styles(k)) for s, e, k in zip(starts, ends, vals)]
        strips.append(Strip(segs, cols))
    if cache is not None:
        cache.keys, cache.strips = keys, list(strips)  # before the crosshair is drawn in
    if crosshair is not None:
        cx, cy = crosshair
        if 0 <= cx < cols and 0 <= cy < rows:
            mark = Strip([Segment(CROSSHAIR, Style(color="#ffff00", bgcolor="#000000",
                                                   bold=True))], 1)
            s = strips[cy]
            strips[cy] = Strip.join([s.crop(0, cx), mark, s.crop(cx + 1, cols)])
    return strips


class Preview(Widget):
    """Shows the newest frame; reports its pixel size, the mouse position and drags."""

    show_crosshair = True  # where keys bump the cloth; the replay, which bumps nothing, has none

    DEFAULT_CSS = """
    Preview { width: 1fr; height: 1fr; }
    """

    class Resized(Message):
        """Posted when the preview is laid out at a new size: it wants images of this many
        pixels (cols × 2·rows)."""

        def __init__(self, width: int, height: int) -> None:
            super().__init__()
            self.width, self.height = width, height

    class Grab(Message):
        """Posted when the mouse is pressed at image point (u, v), both in [0, 1] from the
        top-left."""

        def __init__(self, u: float, v: float) -> None:
            super().__init__()
            self.u, self.v = u, v

    class Drag(Message):
        """Posted when the grabbed point moves by (du, dv) image fractions, on a preview of
        (width_px, height_px) half-block pixels (its columns and twice its rows)."""

        def __init__(self, du: float, dv: float, width_px: int, height_px: int) -> None:
            super().__init__()
            self.du, self.dv = du, dv
            self.width_px, self.height_px = width_px, height_px

    class Release(Message):
        """Posted when the mouse is released after a grab; `pin`: Ctrl was held when it was
        pressed or released (the pin gesture: hold the particle there)."""

        def __init__(self, pin: bool = False) -> None:
            super().__init__()
            self.pin = pin

    class Cut(Message):
        """Posted when the right button drags (the knife) at image point (u, v); `start`: the
        drag begins here."""

        def __init__(self, u: float, v: float, start: bool) -> None:
            super().__init__()
            self.u, self.v, self.start = u, v, start

    def __init__(self, *, id: str | None = None, colors: str = "truecolor") -> None:
        """`colors`: the terminal's colour depth ('truecolor', '256', '16'); below
        truecolor the picture is dithered to the terminal's palette."""
        super().__init__(id=id)
        self._styles = StyleCache()
        self._palette = palette_for(colors)
        self._strips: list[Strip] = []
        self._rows = RowCache()
        self._image: np.ndarray | None = None
        self.pointer: tuple[float, float] | None = None  # mouse over the preview, (u, v)
        self.crosshair: tuple[float, float] = (0.5, 0.5)
        self.frames_shown = 0
        self._drag_from: tuple[float, float] | None = None
        self._pinning = False  # the grab began with Ctrl held
        self._cutting = False  # the right button is down: moves cut instead of drag
        self._placeholder = "waiting for the renderer…"  # shown, centred, until an image

    def show_placeholder(self, text: str) -> None:
        """Text in place of a picture, e.g. why there will be none; wrapped to fit."""
        self._placeholder = text
        self.refresh()

    def on_mount(self) -> None:
        # Textual draws in the console's colour system (truecolor when it names none).
        system = COLOR_SYSTEMS.get(self.app.console.color_system or "truecolor")
        self._styles = StyleCache(color_system=system)
        self._rows = RowCache()  # its strips hold the old cache's styles

    # -- data in -------------------------------------------------------------------------
    def show_image(self, image: np.ndarray) -> None:
        self._image = image
        self._rebuild()
        self.frames_shown += 1

    def move_crosshair(self, dcol: int, drow: int) -> None:
        cols, rows = max(self.size.width, 1), max(self.size.height, 1)
        cx, cy = self._cell(self.crosshair)
        cx = min(max(cx + dcol, 0), cols - 1)
        cy = min(max(cy + drow, 0), rows - 1)
        self.crosshair = ((cx + 0.5) / cols, (cy + 0.5) / rows)
        self._rebuild()

    @property
    def target(self) -> tuple[float, float]:
        """Where a bump applies: under the mouse if it is over the preview, else the crosshair."""
        return self.pointer if self.pointer is not None else self.crosshair

    def _cell(self, uv: tuple[float, float]) -> tuple[int, int]:
        return int(uv[0] * self.size.width), int(uv[1] * self.size.height)

    def _rebuild(self) -> None:
        if self._image is None:
            return
        cols, rows = self.size.width, self.size.height
        crosshair = self._cell(self.crosshair) if self.show_crosshair else None
        self._strips = image_to_strips(self._image, cols, rows, self._styles, crosshair,
                                       self._palette, self._rows)
        self.refresh()

    # -- Line API -------------------------------------------------------------------------
    def get_line_filters(self) -> Sequence[LineFilter]:
        """The app's filters but ANSIToTruecolor: every colour here is RGB already, so that
        filter would only copy each changed row's segments, and at 128² that copying was about
        an eighth of the UI thread's time. (NO_COLOR's and dimming filters still apply.)"""
        return [f for f in super().get_line_filters() if not isinstance(f, ANSIToTruecolor)]

    def render_line(self, y: int) -> Strip:
        if y < len(self._strips):
            return self._strips[y]
        width = self.size.width
        # styled, never None: NO_COLOR's Monochrome filter reads every segment's style
        style = self.rich_style
        if self._image is None:
            lines = textwrap.wrap(self._placeholder, max(width - 2, 1)) or [""]
            k = y - (self.size.height - len(lines)) // 2
            if 0 <= k < len(lines):
                text = lines[k][:width]
                pad = max((width - len(text)) // 2, 0)
                return Strip([Segment(" " * pad + text, style)]).extend_cell_length(width,
                                                                                    style)
        return Strip.blank(width, style)

    def get_content_width(self, container: Size, viewport: Size) -> int:
        return container.width

    def get_content_height(self, container: Size, viewport: Size, width: int) -> int:
        return container.height

    # -- events ---------------------------------------------------------------------------
    def on_resize(self, event: events.Resize) -> None:
        w, h = event.size.width, event.size.height
        if w > 0 and h > 0:
            self.post_message(self.Resized(SCALE * w, SCALE * 2 * h))
            self._rebuild()

    def _uv(self, event: events.MouseEvent) -> tuple[float, float]:
        w, h = max(self.size.width, 1), max(self.size.height, 1)
        return ((event.x + 0.5) / w, (event.y + 0.5) / h)

    def on_mouse_move(self, event: events.MouseMove) -> None:
        self.pointer = self._uv(event)
        if self._cutting:
            self.post_message(self.Cut(*self.pointer, start=False))
        if self._drag_from is not None:
            u, v = self.pointer
            du, dv = u - self._drag_from[0], v - self._drag_from[1]
            if du or dv:
                self._drag_from = (u, v)
                self.post_message(self.Drag(du, dv, self.size.width, 2 * self.size.height))

    def on_leave(self, event: events.Leave) -> None:
        if self._drag_from is None:
            self.pointer = None

    def on_mouse_down(self, event: events.MouseDown) -> None:
        if event.button == 3:  # right button: cut along the drag, do not grab
            self.pointer = self._uv(event)
            self._cutting = True
            self.capture_mouse()
            self.post_message(self.Cut(*self.pointer, start=True))
            return
        self.pointer = self._drag_from = self._uv(event)
        self._pinning = event.ctrl
        self.capture_mouse()
        self.post_message(self.Grab(*self.pointer))

    def on_mouse_up(self, event: events.MouseUp) -> None:
        if self._cutting:
            self._cutting = False
            self.release_mouse()
        if self._drag_from is not None:
            self._drag_from = None
            self.release_mouse()
            self.post_message(self.Release(pin=self._pinning or event.ctrl))
