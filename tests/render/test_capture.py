import os

import numpy as np
import pytest

from cloth_tui.render.capture import (CaptureError, PreviewFile, VideoWriter, ensure_folder,
                                      fit_frame, save_png)

from .service_helpers import count_frames


def frames(n, w, h):
    """Frames that differ (a moving bar), so no encoder merges them."""
    for k in range(n):
        img = np.full((h, w, 3), 40, np.uint8)
        img[:, (k * 3) % w] = 250
        yield img


def test_png_is_written_atomically(tmp_path):
    import imageio.v3 as iio
    img = next(frames(1, 33, 17))
    path = save_png(img, tmp_path / "a.png")
    assert np.array_equal(iio.imread(path), img)
    assert [p.name for p in tmp_path.iterdir()] == ["a.png"]  # no temp left behind


def test_unwritable_folder_raises_capture_error(tmp_path):
    blocker = tmp_path / "file"
    blocker.write_text("x")
    with pytest.raises(CaptureError, match="cannot create captures folder"):
        ensure_folder(blocker / "sub")
    with pytest.raises(CaptureError):
        save_png(np.zeros((4, 4, 3), np.uint8), blocker / "sub" / "a.png")
    if os.geteuid() != 0:  # root writes anywhere
        ro = tmp_path / "ro"
        ro.mkdir(mode=0o500)
        with pytest.raises(CaptureError, match="not writable"):
            ensure_folder(ro)


@pytest.mark.parametrize("w,h", [(64, 48), (65, 47)])
def test_mp4_reads_back_with_every_frame(tmp_path, w, h):
    video = VideoWriter(tmp_path / "v.mp4", 30, (w, h))
    for img in frames(37, w, h):
        video.write(img)
    path = video.close()
    assert path == tmp_path / "v.mp4" and not video.partial.exists()
    assert count_frames(path) == 37


def test_mp4_fragments_are_playable_before_the_end(tmp_path):
    """While recording, the .partial.mp4 already plays: what SIGKILL would leave."""
    import shutil
    import time

    video = VideoWriter(tmp_path / "v.mp4", 10, (64, 48))
    for img in frames(45, 64, 48):  # four and a half 10-frame fragments
        video.write(img)
    deadline = time.monotonic() + 10
    copy = tmp_path / "copy.mp4"
    while time.monotonic() < deadline:
        shutil.copy(video.partial, copy)
        try:
            if count_frames(copy) >= 30:
                break
        except Exception:
            pass
        time.sleep(0.2)
    assert count_frames(copy) >= 30
    video.close()


def test_gif(tmp_path):
    import imageio.v3 as iio
    video = VideoWriter(tmp_path / "v.gif", 10, (31, 21))
    for img in frames(6, 31, 21):
        video.write(img)
    video.close()
    assert iio.imread(tmp_path / "v.gif", index=None).shape == (6, 21, 31, 3)


def test_bad_video_type(tmp_path):
    with pytest.raises(CaptureError):
        VideoWriter(tmp_path / "v.avi", 30, (8, 8))


def test_fit_frame_crops_and_pads_without_rescaling():
    img = np.arange(5 * 4 * 3, dtype=np.uint8).reshape(5, 4, 3)
    assert fit_frame(img, 3, 2).shape == (2, 3, 3)
    padded = fit_frame(img, 6, 7)
    assert padded.shape == (7, 6, 3) and np.array_equal(padded[:5, :4], img)


def test_preview_file_is_rate_limited(tmp_path):
    preview = PreviewFile(tmp_path, rate=5)
    img = np.zeros((8, 8, 3), np.uint8)
    assert preview.offer(img)
    assert not preview.offer(img)  # too soon
    assert preview.offer(img, force=True)
    assert (tmp_path / "preview.png").exists()
