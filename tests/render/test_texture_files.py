"""Texture files as they come: every PNG colour type and bit depth converts to RGB, animated
PNGs give their first frame, large images are downscaled, and damaged or huge files are
refused with one line before they can exhaust memory (issue 19)."""

import contextlib
import io
import resource

import numpy as np
import pytest
from hypothesis import HealthCheck, given, settings
from hypothesis import strategies as st

from cloth_tui import scene as sc
from cloth_tui.png_header import MAX_TEXTURE_PIXELS, MAX_TEXTURE_SIDE
from cloth_tui.render.textures import TextureError, load_texture_image
from . import pngs

DEPTHS = {0: (1, 2, 4, 8, 16), 2: (8, 16), 3: (1, 2, 4, 8), 4: (8, 16), 6: (8, 16)}
settings_files = settings(max_examples=60, deadline=None,
                          suppress_health_check=[HealthCheck.function_scoped_fixture])


def expected_rgb(pixels: np.ndarray, depth: int, colour: int, palette=None) -> np.ndarray:
    """What a PNG's pixels mean as 8-bit RGB, alpha dropped."""
    if colour == 3:
        return np.asarray(palette, np.uint8)[pixels[..., 0]]
    scaled = pixels.astype(np.float64) * 255 / (2**depth - 1)
    channels = scaled[..., : (1 if colour in (0, 4) else 3)]
    return np.repeat(channels, 3 // channels.shape[-1], axis=-1)


@st.composite
def png_images(draw):
    colour = draw(st.sampled_from(sorted(DEPTHS)))
    depth = draw(st.sampled_from(DEPTHS[colour]))
    h, w = draw(st.integers(1, 9)), draw(st.integers(1, 9))
    channels = pngs.CHANNELS[colour]
    seed = draw(st.integers(0, 2**32 - 1))
    rng = np.random.default_rng(seed)
    pixels = rng.integers(0, 2**depth, (h, w, channels))
    palette = rng.integers(0, 256, (2**depth, 3)) if colour == 3 else None
    return pixels, depth, colour, palette


@settings_files
@given(png_images())
def test_every_colour_type_and_depth_converts_to_rgb(tmp_path, image):
    pixels, depth, colour, palette = image
    path = tmp_path / "t.png"
    path.write_bytes(pngs.png(pixels, depth, colour, palette))
    sc.Scene().with_value("appearance.cloth_texture", str(path))
    img = load_texture_image(str(path))
    assert img.dtype == np.uint8 and img.shape == pixels.shape[:2] + (3,)
    assert np.abs(img.astype(float) - expected_rgb(pixels, depth, colour, palette)).max() <= 1


@settings_files
@given(st.integers(1, 4), st.integers(0, 2**32 - 1))
def test_an_animated_png_gives_its_first_frame(tmp_path, extra_frames, seed):
    rng = np.random.default_rng(seed)
    frames = [rng.integers(0, 256, (4, 6, 3)).astype(np.uint8) for _ in range(1 + extra_frames)]
    path = tmp_path / "a.png"
    path.write_bytes(pngs.animated_png(frames))
    assert np.array_equal(load_texture_image(str(path)), frames[0])


@settings_files
@given(st.data())
def test_a_truncated_png_is_refused_in_one_line_or_read_whole(tmp_path, data):
    rng = np.random.default_rng(1)
    pixels = rng.integers(0, 256, (40, 30, 3))
    whole = pngs.png(pixels)
    cut = data.draw(st.integers(0, len(whole) - 1))
    path = tmp_path / "t.png"
    path.write_bytes(whole[:cut])
    try:
        img = load_texture_image(str(path))
    except TextureError as e:
        assert "\n" not in str(e) and str(path) in str(e)
        return
    assert np.array_equal(img, pixels)  # only the end marker was lost


@pytest.mark.parametrize("width,height,depth,colour,whole", [
    (12000, 12000, 1, 0, True),   # a real 17 kB file; took 4 GB when decoded whole
    (20000, 20000, 8, 2, False),  # (the header alone: compressing 1.2 GB of zeros is slow)
    (MAX_TEXTURE_PIXELS + 1, 1, 1, 0, True),
])
def test_a_huge_png_is_refused_from_its_header(tmp_path, width, height, depth, colour, whole):
    path = tmp_path / "huge.png"
    path.write_bytes(pngs.blank_png(width, height, depth, colour) if whole else
                     pngs.header_only(width, height, depth, colour))
    before = resource.getrusage(resource.RUSAGE_SELF).ru_maxrss
    with pytest.raises(TextureError, match=f"{width}×{height}") as e:
        load_texture_image(str(path))
    assert "\n" not in str(e.value)
    with pytest.raises(sc.SceneError, match="pixels"):
        sc.Scene().with_value("appearance.ground_texture", str(path))
    grown_kb = resource.getrusage(resource.RUSAGE_SELF).ru_maxrss - before
    assert grown_kb < 50_000  # refused unread: no decoder allocated the image


@pytest.mark.parametrize("width,height", [(4096, 4096), (3000, 7), (7, 1500)])
def test_a_large_png_is_downscaled_keeping_its_aspect(tmp_path, width, height):
    path = tmp_path / "large.png"
    path.write_bytes(pngs.blank_png(width, height, 1, 0))
    img = load_texture_image(str(path))
    assert max(img.shape[:2]) == MAX_TEXTURE_SIDE
    assert abs(img.shape[1] / img.shape[0] - width / height) <= 0.5 * width / height
    assert img.shape[2] == 3 and img.dtype == np.uint8 and not img.any()


def test_files_that_are_no_png_are_refused(tmp_path):
    for name, data in {"text.png": b"hello", "empty.png": b"",
                       "header.png": pngs.SIGNATURE + b"\0\0\0\x0dIHDR"}.items():
        (tmp_path / name).write_bytes(data)
        with pytest.raises(TextureError):
            load_texture_image(str(tmp_path / name))
        with pytest.raises(sc.SceneError):
            sc.Scene().with_value("appearance.cloth_texture", str(tmp_path / name))


def test_render_refuses_a_texture_it_cannot_decode_with_exit_2(tmp_path):
    from cloth_tui.cli import main

    rng = np.random.default_rng(2)
    texture = tmp_path / "cut.png"
    texture.write_bytes(pngs.png(rng.integers(0, 256, (64, 64, 3)))[:600])
    err = io.StringIO()
    with contextlib.redirect_stderr(err):
        code = main(["render", "default", "--set", f"appearance.cloth_texture={texture}",
                     "-o", str(tmp_path / "out.png")])
    assert code == 2
    lines = err.getvalue().splitlines()
    assert len(lines) == 1 and "cut.png" in lines[0] and "truncated" in lines[0]
    assert not (tmp_path / "out.png").exists()
