"""The contact sheet: the wedge's thumbnails in a labelled grid (see plan.Layout for which
key runs where), each captioned with its stretch, energy drift and time. Labels and captions
are drawn once (Pillow); a clip sheet pastes each cell's frame k into that background for
frame k. Runs that did not finish (cancelled, failed) are grey, saying why."""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np

from .engine import Failed
from .plan import Cell, Layout, Vary, label

MARGIN, GAP, LINE, CAPTION = 10, 6, 20, 18   # px
FONT_SIZE, CAPTION_FONT_SIZE = 14, 12
BACKGROUND, INK, MUTED, EMPTY = (246, 246, 246), (30, 30, 30), (110, 110, 110), (200, 200, 200)
VIDEO_BLOCK = 16  # MP4 frame sides are multiples of this (H.264 macroblocks)


def caption(result) -> str:
    if result is None:
        return "not run (cancelled)"
    if isinstance(result, Failed):
        return "failed: " + result.reason
    halted = "  HALTED" if result["halted"] else ""
    return (f"stretch {100 * result['max_stretch']:.1f} %  drift {result['energy_drift']:+.3g} J  "
            f"{result['wall_s']:.2f} s{halted}")


@dataclass
class Sheet:
    """The background with every label, and where each cell's picture goes."""
    background: np.ndarray                 # (H, W, 3) uint8
    boxes: list[tuple[int, int]]           # top-left (x, y) of each cell's picture
    thumb: tuple[int, int]                 # (w, h)

    def frame(self, pictures: list[np.ndarray | None]) -> np.ndarray:
        out = self.background.copy()
        w, h = self.thumb
        for (x, y), pic in zip(self.boxes, pictures):
            if pic is not None:
                out[y:y + h, x:x + w] = pic[:h, :w]
        return out


def _fonts():
    from PIL import ImageFont
    return ImageFont.load_default(size=FONT_SIZE), ImageFont.load_default(size=CAPTION_FONT_SIZE)


def _fit(draw, text: str, font, width: int) -> str:
    """Cut `text` with an ellipsis to fit `width` px."""
    if draw.textlength(text, font=font) <= width:
        return text
    while text and draw.textlength(text + "…", font=font) > width:
        text = text[:-1]
    return text + "…"


def layout_sheet(varies: list[Vary], cells: list[Cell], results: list, thumb: tuple[int, int],
                 title: str, block: int = 1) -> Sheet:
    """Draw the labels and captions; `block`: round the sides up to a multiple of it."""
    from PIL import Image, ImageDraw

    lay = Layout.of(varies)
    font, small = _fonts()
    probe = ImageDraw.Draw(Image.new("RGB", (1, 1)))
    tw, th = thumb
    # one label column per row key, as wide as its widest label
    label_w = [int(max(probe.textlength(label(v.key, x), font=font) for x in v.values)) + GAP
               for v in lay.row_keys]
    left = MARGIN + sum(label_w)
    top = MARGIN + LINE * (1 + len(lay.col_keys))
    pitch_x, pitch_y = tw + GAP, th + CAPTION + GAP
    width = left + lay.cols * pitch_x - GAP + MARGIN
    height = top + lay.rows * pitch_y - GAP + MARGIN
    width, height = -(-width // block) * block, -(-height // block) * block
    img = Image.new("RGB", (width, height), BACKGROUND)
    draw = ImageDraw.Draw(img)
    draw.text((MARGIN, MARGIN), _fit(draw, title, font, width - 2 * MARGIN), fill=INK, font=font)
    span = lay.cols
    for k, v in enumerate(lay.col_keys):  # outer keys first: each label spans its block
        span //= len(v.values)
        y = MARGIN + LINE * (1 + k)
        for b in range(lay.cols // span):
            x0 = left + b * span * pitch_x
            text = _fit(draw, label(v.key, v.values[b % len(v.values)]), font, span * pitch_x - GAP)
            draw.text((x0 + (span * pitch_x - GAP - draw.textlength(text, font=font)) / 2, y),
                      text, fill=INK, font=font)
            if span > 1:
                draw.line((x0, y + LINE - 3, x0 + span * pitch_x - GAP, y + LINE - 3), fill=MUTED)
    span = lay.rows
    x = MARGIN
    for k, v in enumerate(lay.row_keys):
        span //= len(v.values)
        for b in range(lay.rows // span):
            y0 = top + b * span * pitch_y
            draw.text((x, y0 + (span * pitch_y - GAP - LINE) / 2),
                      label(v.key, v.values[b % len(v.values)]), fill=INK, font=font)
        x += label_w[k]
    boxes = []
    for cell, result in zip(cells, results):
        r, c = lay.position(varies, cell)
        bx, by = left + c * pitch_x, top + r * pitch_y
        boxes.append((bx, by))
        if result is None or isinstance(result, Failed):
            draw.rectangle((bx, by, bx + tw - 1, by + th - 1), fill=EMPTY)
        draw.text((bx, by + th + 2), _fit(draw, caption(result), small, tw), font=small,
                  fill=INK if isinstance(result, dict) else MUTED)
    return Sheet(np.asarray(img, dtype=np.uint8).copy(), boxes, thumb)


def title_of(scene_name: str, frames: int, varies: list[Vary]) -> str:
    fixed = [label(v.key, v.values[0]) for v in Layout.of(varies).fixed]
    return "  ·  ".join([f"wedge of {scene_name}", f"{frames} frames"] + fixed)


def still(sheet: Sheet, results: list) -> np.ndarray:
    return sheet.frame([r["image"] if isinstance(r, dict) else None for r in results])


def clip_frames(sheet: Sheet, results: list, frames: int):
    """The sheet's frames, one per simulated frame; a cell without a clip stays grey."""
    for k in range(frames):
        yield sheet.frame([r["clip"][min(k, len(r["clip"]) - 1)] if isinstance(r, dict)
                           else None for r in results])
