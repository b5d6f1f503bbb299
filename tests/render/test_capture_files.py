"""Files a capture writes: temporaries created exclusively (no writing through a planted link,
no overwriting an existing partial file); a full disk is named as such, leaves no empty files,
and the preview file recovers when writing works again."""

import errno
import os
import subprocess
from types import SimpleNamespace

import numpy as np
import pytest

from cloth_tui.render.capture import CaptureError, PreviewFile, VideoWriter
from cloth_tui.util import atomic_write

FULL = OSError(errno.ENOSPC, os.strerror(errno.ENOSPC))


def _record(path, n=3, size=(32, 24)):
    video = VideoWriter(path, 10, size)
    rng = np.random.default_rng(0)
    try:
        for _ in range(n):  # noise: incompressible, so a small disk fills
            video.write(rng.integers(0, 256, (size[1], size[0], 3), dtype=np.uint8))
        return video.close()
    finally:
        video.abort()  # after a failure: ffmpeg gone before the test looks


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


def test_preview_file_recovers_after_a_failed_write(tmp_path, monkeypatch):
    image = np.zeros((8, 8, 3), np.uint8)
    preview = PreviewFile(tmp_path)
    real_replace = os.replace

    def full(*args, **kwargs):
        raise FULL

    monkeypatch.setattr(os, "replace", full)
    with pytest.raises(CaptureError, match="(?i)no space left on device"):
        preview.offer(image, force=True)
    assert preview.offer(image, force=True) is False  # reported once, not again
    monkeypatch.setattr(os, "replace", real_replace)
    assert preview.offer(image, force=True) is True
    assert [p.name for p in tmp_path.iterdir()] == ["preview.png"]


def test_broken_encoder_pipe_on_a_full_disk_says_no_space(tmp_path, monkeypatch):
    """ffmpeg exits on a full disk; all we see is EPIPE on its pipe."""
    import imageio_ffmpeg

    def ffmpeg_on_a_full_disk(*args, **kwargs):
        yield  # started
        raise BrokenPipeError(errno.EPIPE, os.strerror(errno.EPIPE))

    monkeypatch.setattr(imageio_ffmpeg, "write_frames", ffmpeg_on_a_full_disk)
    monkeypatch.setattr(os, "statvfs", lambda _: SimpleNamespace(f_bavail=0, f_frsize=4096))
    video = VideoWriter(tmp_path / "v.mp4", 10, (32, 24))
    with pytest.raises(CaptureError, match="(?i)no space left on device"):
        video.write(np.zeros((24, 32, 3), np.uint8))
    assert list(tmp_path.iterdir()) == []  # no empty .partial.mp4


@pytest.fixture
def full_tmpfs(tmp_path):
    """A real 64 kB file system, filled up (needs the right to mount; skipped otherwise)."""
    mnt = tmp_path / "tiny"
    mnt.mkdir()
    if os.geteuid() != 0 or subprocess.run(["mount", "-t", "tmpfs", "-o", "size=64k", "tmpfs",
                                            str(mnt)], capture_output=True).returncode:
        pytest.skip("cannot mount a tmpfs here")
    try:
        with open(mnt / "filler", "wb") as fh:
            with pytest.raises(OSError):
                fh.write(b"\0" * (1 << 20))
                fh.flush()
        yield mnt
    finally:
        subprocess.run(["umount", "-l", str(mnt)], check=False)


def test_mp4_on_a_really_full_disk(full_tmpfs):
    with pytest.raises(CaptureError, match="(?i)no space left on device"):
        _record(full_tmpfs / "v.mp4", n=300, size=(320, 240))
    assert sorted(p.name for p in full_tmpfs.iterdir()) == ["filler"]


def test_gif_past_its_length_is_refused_in_one_line_before_any_work(tmp_path, capsys,
                                                                      monkeypatch):
    from cloth_tui.cli import main
    from cloth_tui.render import cli as render_cli
    from cloth_tui.render.probe import RendererUnavailable

    def no_work(*args, **kwargs):  # the refusal must come before the renderer is asked for
        raise RendererUnavailable("reached the renderer")

    monkeypatch.setattr(render_cli, "require_renderer", no_work)
    out = tmp_path / "x.gif"
    assert main(["render", "default", "-o", str(out), "--frames", "100000"]) == 2
    err = capsys.readouterr().err
    assert err.count("\n") == 1 and "at most 325 frames at 640x480" in err
    assert not out.exists()


def test_gif_writer_stops_at_its_length(tmp_path, monkeypatch):
    from cloth_tui.render import capture

    monkeypatch.setattr(capture, "GIF_MAX_PIXELS", 3 * 8 * 8)
    video = VideoWriter(tmp_path / "a.gif", 10, (8, 8))
    for _ in range(3):
        video.write(np.zeros((8, 8, 3), np.uint8))
    with pytest.raises(CaptureError, match="at most 3 frames"):
        video.write(np.zeros((8, 8, 3), np.uint8))


def test_an_mp4_render_on_a_full_disk_prints_one_line(tmp_path, capfd):
    from cloth_tui.cli import main
    from tests.small_disk import small_tmpfs

    with small_tmpfs(tmp_path / "small", "16k") as disk:
        rc = main(["render", "default", "-o", str(disk / "v.mp4"), "--frames", "60",
                   "--size", "640x480", "--set", "cloth.resolution=10"])
        err = capfd.readouterr().err
        assert rc == 2 and err.count("\n") == 1, err  # ffmpeg's own lines do not reach it
        assert "No space left on device" in err
        assert not (disk / "v.mp4").exists()
