"""The true-pixel preview in the app: render size from the cells' pixels, frames written as
kitty/sixel escapes at the preview's top-left cell, the mode in the status line; and the
half-block preview dithered when the terminal has 256 colours."""

import asyncio
import base64
import re
import zlib

import numpy as np
import pytest

from cloth_tui.tui.graphics.detect import Graphics
from cloth_tui.tui.pixel_preview import MAX_PIXELS, PixelPreview, render_size
from cloth_tui.tui.preview import Preview
from cloth_tui.tui.textual_adapter import driver_of

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
            driver = driver_of(app)
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
    assert frame.endswith("\x1b8")
    at_top_left = f"\x1b[{region.y + 1};{region.x + 1}H"
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
        where = (place[0]["x"], place[0]["y"], place[0]["w"], place[0]["h"])
        assert where == ("0", "0", str(w), str(h))
        assert at_top_left + "\x1b_Ga=p" in frame
    else:
        assert at_top_left + f'\x1bP0;1;0q"1;1;{w};{h}' in frame
        assert frame.rstrip("\x1b8").endswith("\x1b\\")


def test_half_blocks_are_dithered_to_the_cube_when_the_terminal_has_256_colours(tmp_path):
    async def go():
        app = make_app(tmp_path, graphics=Graphics("blocks", (9, 20), "256"))
        async with app.run_test(size=SIZE) as pilot:
            assert app.console.color_system == "256"
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
            driver = driver_of(app)
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


PLACE = re.compile(r"\x1b\[(\d+);(\d+)H\x1b_G(a=p[^\x1b]*)\x1b\\")
SIXEL = re.compile(r"\x1b\[(\d+);(\d+)H\x1bP0;1;0q\"1;1;(\d+);(\d+)")


def kitty_boxes(stream: str) -> list[tuple[int, int, int, int]]:
    """(x, y, width, height) in 0-based cells of each kitty placement in the stream."""
    out = []
    for row, col, keys in PLACE.findall(stream):
        k = dict(kv.split("=") for kv in keys.split(","))
        out.append((int(col) - 1, int(row) - 1, int(k["c"]), int(k["r"])))
    return out


def sixel_boxes(stream: str, cell_px) -> list[tuple[int, int, int, int]]:
    """The same for each sixel image, from its pixel size (cells it reaches into)."""
    cw, ch = cell_px
    return [(int(col) - 1, int(row) - 1, -(-int(w) // cw), -(-int(h) // ch))
            for row, col, w, h in SIXEL.findall(stream)]


def overlaps(box, region) -> bool:
    x, y, w, h = box
    return x < region.right and region.x < x + w and y < region.bottom and region.y < y + h


@pytest.mark.parametrize("mode", ["kitty", "sixel"])
def test_around_a_notice_the_picture_goes_on_beside_it(tmp_path, mode):
    written: list[str] = []
    cell = (9, 20)

    async def go():
        # 100 columns: sixel's picture (900 × 540 pixels) fills the preview to its last row
        app = make_app(tmp_path, graphics=Graphics(mode, cell, "truecolor"))
        async with app.run_test(size=(100, 30), notifications=True) as pilot:
            driver = driver_of(app)
            original = driver.write

            def write(data):  # what was written once the notice was on the screen
                if any(t.region.area for t in app.screen.query("Toast")):
                    written.append(data)
                original(data)

            driver.write = write
            preview = app.preview
            await until(pilot, lambda: preview.frames_written >= 1, what="a frame")
            app.notify("a notice that must stay readable", timeout=30)
            await until(pilot, lambda: bool(app.screen.query("Toast")), what="the notice")
            await pilot.pause(0.3)
            toast = app.screen.query_one("Toast").region
            assert toast.overlaps(preview.region)
            if mode == "kitty":  # at once, before any new frame: off the notice's cells
                boxes = kitty_boxes("".join(written).split("a=t")[0])
                assert boxes, "the picture was not moved when the notice came"
                assert not any(overlaps(b, toast) for b in boxes)
            written.clear()
            before = preview.frames_written
            preview.move_crosshair(0, 0)  # a new frame (the simulation is paused)
            await until(pilot, lambda: preview.frames_written > before, what="a frame")
            stream = "".join(written)
            boxes = kitty_boxes(stream) if mode == "kitty" else sixel_boxes(stream, cell)
            region = preview.content_region
            assert not any(overlaps(b, toast) for b in boxes)
            covered = sum(w * h for *_, w, h in boxes)
            hidden = toast.intersection(region).area
            assert covered == region.area - hidden  # all the rest, the rows beside it too
            beside = [b for b in boxes if b[1] >= toast.y]
            assert beside and beside[0][0] == region.x and beside[0][2] == toast.x - region.x
    run(go())


@pytest.mark.parametrize("mode", ["kitty", "sixel"])
def test_the_drawer_opens_over_the_picture_at_once(tmp_path, mode):
    written: list[str] = []  # what was written once the drawer was on the screen
    cell = (9, 20)

    async def go():
        app = make_app(tmp_path, graphics=Graphics(mode, cell, "truecolor"))
        async with app.run_test(size=(100, 30)) as pilot:
            drawer = app.query_one("#controls")
            driver = driver_of(app)
            original = driver.write

            def write(data):
                if drawer.display and drawer.region.width > 0:
                    written.append(data)
                original(data)

            driver.write = write
            preview = app.preview
            await until(pilot, lambda: preview.frames_written >= 1, what="a frame")
            before = preview.frames_written
            await pilot.press("c")  # narrow: the drawer opens over the preview
            await until(pilot, lambda: drawer.display and drawer.region.width > 0,
                        what="the drawer")
            await pilot.pause(0.2)
            if mode == "kitty":  # moved off the drawer before any new frame
                boxes = kitty_boxes("".join(written).split("a=t")[0])
                assert boxes, "the picture was not moved when the drawer opened"
                assert not any(overlaps(b, drawer.region) for b in boxes)
            preview.move_crosshair(0, 0)  # a new frame, cut for the open drawer
            await until(pilot, lambda: preview.frames_written > before + 1, what="a frame")
            stream = "".join(written)
            boxes = kitty_boxes(stream) if mode == "kitty" else sixel_boxes(stream, cell)
            assert boxes and not any(overlaps(b, drawer.region) for b in boxes)
            assert max(x + w for x, _, w, _ in boxes) == drawer.region.x  # up to its edge
    run(go())


def test_cells_the_picture_leaves_are_the_scene_background(tmp_path):
    async def go():
        app = make_app(tmp_path, graphics=Graphics("sixel", (9, 20), "truecolor"))
        async with app.run_test(size=SIZE) as pilot:
            preview = app.preview
            await until(pilot, lambda: preview.frames_written >= 1, what="a frame")
            strip = preview.render_line(0)
            fog = app.scene.appearance.fog_color
            assert {seg.style.bgcolor.name for seg in strip} == {fog}
            app.set_value("appearance.fog_color", "#203040")
            preview.show_image(preview._image)
            strip = preview.render_line(0)
            assert {seg.style.bgcolor.name for seg in strip} == {"#203040"}
            assert preview.layout().fill_sgr == "48;2;32;48;64"  # the erased cells' too
    run(go())
