"""The true-pixel preview in the app: render size from the cells' pixels, frames written as
kitty/sixel escapes at the preview's top-left cell, the mode in the status line; and the
half-block preview dithered when the terminal has 256 colours."""

import asyncio
import base64
import re
import zlib

import numpy as np
import pytest
from rich.color import ColorSystem

from cloth_tui.tui.graphics.detect import Graphics
from cloth_tui.tui.pixel_preview import MAX_PIXELS, PixelPreview, render_size
from cloth_tui.tui.preview import Preview

from .conftest import SIZE, make_app, until


def test_render_size_is_the_cells_pixels_within_limits():
    w, h = render_size(100, 40, (9, 20), "kitty")  # 900 × 800 is more than MAX_PIXELS
    assert w * h <= MAX_PIXELS and w * h > 0.95 * MAX_PIXELS and abs(w / h - 900 / 800) < 0.01
    w, h = render_size(60, 20, (8, 16), "kitty")
    assert (w, h) == (480, 320)  # small enough: exactly the cells' pixels
    w, h = render_size(150, 45, (9, 20), "sixel")
    assert max(w, h) <= 1000 and abs(w / h - 1350 / 900) < 0.01
    assert render_size(110, 40, (9, 18), "sixel") == (990, 720)


def run(coro):
    return asyncio.run(coro)


@pytest.mark.parametrize("mode", ["kitty", "sixel"])
def test_frames_are_written_at_the_preview_cell_with_the_cells_pixel_size(tmp_path, mode):
    written: list[str] = []

    async def go():
        app = make_app(tmp_path, graphics=Graphics(mode, (9, 20), "truecolor"))
        async with app.run_test(size=SIZE) as pilot:
            driver = app._driver
            original = driver.write
            driver.write = lambda data: (written.append(data), original(data))
            preview = app.preview
            assert isinstance(preview, PixelPreview)
            await until(pilot, lambda: preview.frames_written >= 2, what="frames written")
            region = preview.content_region
            renderer = app.renderer
            assert renderer.size == render_size(region.width, region.height, (9, 20), mode)
            app._refresh_status()
            await pilot.pause(0.1)
            status = str(app.query_one("#status-text").render())
            assert f"({mode})" in status
            return region, renderer.size

    region, (w, h) = run(go())
    frames = [d for d in written if d.startswith("\x1b7")]
    assert frames
    frame = frames[-1]
    assert frame.startswith(f"\x1b7\x1b[{region.y + 1};{region.x + 1}H") and frame.endswith("\x1b8")
    if mode == "kitty":
        chunks = re.findall(r"\x1b_G([^;\x1b]*);?([^\x1b]*)\x1b\\", frame)
        head = dict(kv.split("=") for kv in chunks[0][0].split(","))
        assert (int(head["s"]), int(head["v"])) == (w, h)
        payload = "".join(p for keys, p in chunks if "a=p" not in keys and "a=d" not in keys)
        pixels = np.frombuffer(zlib.decompress(base64.b64decode(payload)), np.uint8)
        image = pixels.reshape(h, w, 3)
        assert len(np.unique(image.reshape(-1, 3), axis=0)) >= 3  # fog, cloth, crosshair
        place = [dict(kv.split("=") for kv in k.split(",")) for k, _ in chunks if "a=p" in k]
        assert (int(place[0]["c"]), int(place[0]["r"])) == (region.width, region.height)
    else:
        assert f'"1;1;{w};{h}' in frame and frame.rstrip("\x1b8").endswith("\x1b\\")


def test_half_blocks_are_dithered_to_the_cube_when_the_terminal_has_256_colours(tmp_path):
    async def go():
        app = make_app(tmp_path, graphics=Graphics("blocks", (9, 20), "256"))
        async with app.run_test(size=SIZE) as pilot:
            assert app.console._color_system == ColorSystem.EIGHT_BIT
            preview = app.preview
            assert not isinstance(preview, PixelPreview) and isinstance(preview, Preview)
            await until(pilot, lambda: preview.frames_shown > 0, what="a frame")
            w, h = preview.size
            # a gradient: dithered, it becomes patterns of cube colours
            y, x = np.mgrid[0:4 * h, 0:2 * w]
            ramp = np.stack([x * 255 // (2 * w), y * 255 // (4 * h), 0 * x + 60], -1)
            preview.show_image(ramp.astype(np.uint8))
            levels = {0, 95, 135, 175, 215, 255}
            colours = set()
            for strip in preview._strips:
                for seg in strip:
                    for c in (seg.style.color, seg.style.bgcolor):
                        colours.add(tuple(c.triplet))
            assert all(set(c) <= levels for c in colours)
            assert len(colours) > 20
    run(go())


def test_a_screen_over_the_preview_takes_the_kitty_picture_away_and_back(tmp_path):
    from textual.screen import ModalScreen
    from textual.widgets import Static

    class Cover(ModalScreen):
        def compose(self):
            yield Static("over the preview")

    written: list[str] = []

    async def go():
        app = make_app(tmp_path, graphics=Graphics("kitty", (9, 20), "truecolor"))
        async with app.run_test(size=SIZE) as pilot:
            driver = app._driver
            original = driver.write
            driver.write = lambda data: (written.append(data), original(data))
            preview = app.preview
            await until(pilot, lambda: preview.frames_written >= 1, what="a frame")
            before = preview.frames_written
            written.clear()
            app.push_screen(Cover())
            await pilot.pause(0.3)
            deletes = [d for d in written if "a=d" in d]
            assert deletes and not any("a=p" in d for d in written)  # paused: no new frame
            app.pop_screen()
            await until(pilot, lambda: preview.frames_written > before, what="drawn again")
            assert any("a=p" in d for d in written[written.index(deletes[-1]):])
    run(go())


def test_the_picture_stops_above_a_notice_over_the_preview(tmp_path):
    written: list[str] = []

    async def go():
        app = make_app(tmp_path, graphics=Graphics("kitty", (9, 20), "truecolor"))
        async with app.run_test(size=SIZE, notifications=True) as pilot:
            driver = app._driver
            original = driver.write
            driver.write = lambda data: (written.append(data), original(data))
            preview = app.preview
            await until(pilot, lambda: preview.frames_written >= 1, what="a frame")
            await pilot.press("c")  # controls hidden: the preview spans the screen
            await pilot.pause(0.3)
            rows = preview.size.height
            app.notify("a notice that must stay readable", timeout=30)
            await pilot.pause(0.3)
            toast = app.screen.query_one("Toast")
            assert toast.region.overlaps(preview.region)
            written.clear()
            preview.move_crosshair(0, 0)  # a new frame (the simulation is paused)
            await until(pilot, lambda: any("a=p" in d for d in written), what="a frame")
            place = re.search(r"a=p[^\x1b]*,r=(\d+)", "".join(written))
            shown = int(place.group(1))
            assert shown == toast.region.y - preview.region.y < rows
    run(go())
