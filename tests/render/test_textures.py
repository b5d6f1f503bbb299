import subprocess
import sys

import numpy as np

from cloth_tui.render.textures import (GENERATORS, grass_image, load_texture_image,
                                       maze_image)
from cloth_tui.resources import textures_dir
from cloth_tui.scene import Scene
from cloth_tui.texture_names import BUILTIN_TEXTURES


def test_builtin_textures_are_committed_small_pngs():
    for name in GENERATORS:
        path = textures_dir() / f"{name}.png"
        assert path.is_file() and path.stat().st_size < 16_000
        img = load_texture_image(name)
        assert img.dtype == np.uint8 and img.ndim == 3 and img.shape[2] == 3
        assert img.std() > 10  # a pattern, not a flat colour


def test_the_scene_accepts_exactly_the_textures_there_are_generators_for():
    assert set(GENERATORS) == set(BUILTIN_TEXTURES)
    for name in BUILTIN_TEXTURES:
        assert Scene().with_value("appearance.cloth_texture", name).appearance.cloth_texture == name


def test_generators_are_deterministic_and_tile():
    assert np.array_equal(maze_image(), maze_image())
    g = grass_image().astype(int)
    # Seamless: the wrap-around step is no larger than ordinary neighbour steps.
    assert np.abs(g[0] - g[-1]).mean() < 3 * np.abs(np.diff(g, axis=0)).mean() + 1


def test_png_path_and_grey_images(tmp_path):
    import imageio.v3 as iio
    grey = (np.arange(64, dtype=np.uint8).reshape(8, 8) * 4)
    iio.imwrite(tmp_path / "g.png", grey)
    img = load_texture_image(str(tmp_path / "g.png"))
    assert img.shape == (8, 8, 3)
    assert load_texture_image("none") is None


def test_cli_import_stays_light():
    code = ("import sys, cloth_tui.cli, cloth_tui.render.cli; "
            "print([m for m in ('pyvista', 'vtkmodules', 'imageio') if m in sys.modules])")
    out = subprocess.run([sys.executable, "-c", code], capture_output=True, text=True,
                         check=True).stdout.strip()
    assert out == "[]"
