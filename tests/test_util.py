import os
import stat

import pytest

from cloth_tui.util import atomic_write


@pytest.fixture(params=[0o022, 0o002, 0o077])
def umask(request):
    old = os.umask(request.param)
    yield request.param
    os.umask(old)


def mode(path):
    return stat.S_IMODE(path.stat().st_mode)


def test_atomic_write_follows_the_umask(tmp_path, umask):
    path = tmp_path / "a.bin"
    with atomic_write(path) as fh:
        fh.write(b"abc")
    assert path.read_bytes() == b"abc"
    assert mode(path) == 0o666 & ~umask


def test_atomic_write_replaces_whole_or_not_at_all(tmp_path):
    path = tmp_path / "a.txt"
    path.write_text("old")
    with pytest.raises(RuntimeError):
        with atomic_write(path, "w", encoding="utf-8") as fh:
            fh.write("half of the new")
            raise RuntimeError("crash while writing")
    assert path.read_text() == "old"
    assert [p.name for p in tmp_path.iterdir()] == ["a.txt"]  # no temp left behind
    with atomic_write(path, "w", encoding="utf-8", durable=False) as fh:
        fh.write("new")
    assert path.read_text() == "new"
    assert [p.name for p in tmp_path.iterdir()] == ["a.txt"]


def test_saved_scene_follows_the_umask(tmp_path, umask):
    from cloth_tui.scene import Scene
    from cloth_tui.scene_files import load, save
    path = save(Scene(), tmp_path / "s.toml")
    assert mode(path) == 0o666 & ~umask
    assert load(path).cloth == Scene().cloth


def test_captures_follow_the_umask(tmp_path, umask):
    import numpy as np

    from cloth_tui.render.capture import VideoWriter, save_png
    png = save_png(np.zeros((4, 6, 3), np.uint8), tmp_path / "a.png")
    assert mode(png) == 0o666 & ~umask
    video = VideoWriter(tmp_path / "v.gif", 10, (6, 4))
    video.write(np.zeros((4, 6, 3), np.uint8))
    assert mode(video.close()) == 0o666 & ~umask
