"""Files a capture writes: temporaries created exclusively (no writing through a planted link,
no overwriting an existing partial file)."""

import os

import numpy as np

from cloth_tui.render.capture import VideoWriter
from cloth_tui.util import atomic_write


def _record(path, n=3, size=(32, 24)):
    video = VideoWriter(path, 10, size)
    for k in range(n):
        img = np.full((size[1], size[0], 3), 40 + 50 * k, np.uint8)
        video.write(img)
    return video.close()


def test_mp4_does_not_write_through_a_link_planted_at_its_partial_name(tmp_path):
    elsewhere = tmp_path / "elsewhere"
    elsewhere.mkdir()
    out_dir = tmp_path / "out"
    out_dir.mkdir()
    (out_dir / "out.partial.mp4").symlink_to(elsewhere / "stolen.mp4")  # dangling
    path = _record(out_dir / "out.mp4")
    assert path == out_dir / "out.mp4" and path.is_file() and not path.is_symlink()
    assert path.stat().st_size > 0
    assert not (elsewhere / "stolen.mp4").exists()
    assert (out_dir / "out.partial.mp4").is_symlink()  # left as it was


def test_mp4_does_not_overwrite_an_existing_partial_file(tmp_path):
    keep = tmp_path / "keep.partial.mp4"
    keep.write_bytes(b"an earlier recording")
    _record(tmp_path / "keep.mp4")
    assert keep.read_bytes() == b"an earlier recording"
    assert (tmp_path / "keep.mp4").stat().st_size > 0
    assert sorted(p.name for p in tmp_path.iterdir()) == ["keep.mp4", "keep.partial.mp4"]


def test_finished_file_replaces_a_link_at_the_target_not_its_target(tmp_path):
    victim = tmp_path / "victim.txt"
    victim.write_text("precious")
    (tmp_path / "a.gif").symlink_to(victim)
    _record(tmp_path / "a.gif")
    assert victim.read_text() == "precious"
    assert not (tmp_path / "a.gif").is_symlink()


def test_atomic_write_temporaries_are_exclusive_and_follow_no_link(tmp_path, monkeypatch):
    opened = []
    real_open = os.open

    def spy(path, flags, *args, **kwargs):
        opened.append(flags)
        return real_open(path, flags, *args, **kwargs)

    monkeypatch.setattr(os, "open", spy)
    with atomic_write(tmp_path / "x.bin") as fh:
        fh.write(b"x")
    assert opened and all(f & os.O_EXCL and f & os.O_NOFOLLOW for f in opened)
