"""Writing pictures to disk: screenshots (PNG), videos (MP4, GIF) and the rate-limited preview
file. Nothing here touches VTK; images come in as (H, W, 3) uint8 arrays.

Crash safety:
- PNG (screenshots, preview.png) is written to a temp name beside the target and renamed, so a
  reader never sees half a file.
- MP4 is H.264 in *fragmented* MP4, a self-contained fragment about every second (GOP = fps).
  While recording, the file is `NAME.partial.mp4` (or `NAME.K.partial.mp4` if that name is
  taken), created exclusively: never through a symbolic link planted there, never over an
  existing file. A clean finish renames it over `NAME.mp4`.
  If the process is killed (even SIGKILL), `NAME.partial.mp4` stays behind and plays up to its
  last complete fragment: there is no index at the end to lose.
- GIF frames are held in memory and written (temp name, then rename) when the video ends;
  a killed GIF recording leaves nothing. So a GIF is bounded: at most GIF_MAX_PIXELS pixels
  over all its frames (325 frames at 640×480); longer videos are for MP4.
Finished files are written by util.atomic_write and get the permissions the umask gives.
Every failure to write surfaces as CaptureError with a one-line message.
"""

from __future__ import annotations

import contextlib
import errno
import os
import time
from datetime import datetime
from pathlib import Path

import numpy as np

from ..util import EXCLUSIVE_NEW_FILE, NEW_FILE_MODE, atomic_write

VIDEO_SUFFIXES = (".mp4", ".gif")
PREVIEW_NAME = "preview.png"
# frames × width × height of one GIF: ~300 MB held as RGB, about as much again to encode
GIF_MAX_PIXELS = 100_000_000
PREVIEW_RETRY_S = 2.0  # after a failed preview write, try again this often (quietly)
NEARLY_FULL_BYTES = 1 << 20  # free space below which a broken encoder is blamed on the disk
NO_SPACE = os.strerror(errno.ENOSPC)


class CaptureError(Exception):
    """A capture could not be written (folder missing or read-only, disk full, encoder
    failure). The message is one line, fit to show the user."""


def _reason(e: BaseException) -> str:
    text = getattr(e, "strerror", None) or str(e).strip()
    return text.splitlines()[0] if text else type(e).__name__


def _encoder_failure(e: BaseException, folder: Path) -> str:
    """Why the encoder stopped. ffmpeg writing to a full disk exits, and we only see our pipe
    to it break (EPIPE): when the folder has no room left, name that, the real cause."""
    if isinstance(e, OSError) and e.errno == errno.ENOSPC:
        return NO_SPACE
    try:
        st = os.statvfs(folder)
    except OSError:
        return _reason(e)
    return NO_SPACE if st.f_bavail * st.f_frsize < NEARLY_FULL_BYTES else _reason(e)


def gif_max_frames(size: tuple[int, int]) -> int:
    """The most frames a GIF of this size may have (GIF_MAX_PIXELS)."""
    return max(1, GIF_MAX_PIXELS // max(1, size[0] * size[1]))


def ensure_folder(folder: Path) -> Path:
    """Create the captures folder if needed; CaptureError if it cannot be written."""
    folder = Path(folder)
    try:
        folder.mkdir(parents=True, exist_ok=True)
    except OSError as e:
        raise CaptureError(f"cannot create captures folder {folder}: {_reason(e)}") from None
    if not os.access(folder, os.W_OK | os.X_OK):
        raise CaptureError(f"captures folder {folder} is not writable")
    return folder


def timestamped(folder: Path, prefix: str, suffix: str) -> Path:
    """A new file name in `folder`, e.g. cloth-20260101-120000.png, never an existing one."""
    stamp = datetime.now().strftime("%Y%m%d-%H%M%S")
    path = folder / f"{prefix}-{stamp}{suffix}"
    k = 1
    while path.exists() or path.with_name(partial_name(path)).exists():
        k += 1
        path = folder / f"{prefix}-{stamp}-{k}{suffix}"
    return path


def partial_name(path: Path) -> str:
    return f"{path.stem}.partial{path.suffix}"


def claim_partial(path: Path) -> Path:
    """Create the temporary file a recording is written to, exclusively (O_EXCL, no link
    followed): `NAME.partial.mp4`, or `NAME.2.partial.mp4`… when that exists."""
    for k in range(1, 1000):
        stem = path.stem if k == 1 else f"{path.stem}.{k}"
        candidate = path.with_name(f"{stem}.partial{path.suffix}")
        try:
            os.close(os.open(candidate, EXCLUSIVE_NEW_FILE, NEW_FILE_MODE))
        except FileExistsError:
            continue
        except OSError as e:
            raise CaptureError(f"cannot write {path}: {_reason(e)}") from None
        return candidate
    raise CaptureError(f"cannot write {path}: no free temporary name beside it")


def save_png(image: np.ndarray, path: Path, compress_level: int = 6,
             durable: bool = True) -> Path:
    """Write atomically (util.atomic_write: temp file in the same folder, then rename)."""
    import imageio.v3 as iio

    path = Path(path)
    data = iio.imwrite("<bytes>", np.ascontiguousarray(image), extension=".png",
                       compress_level=compress_level)
    try:
        with atomic_write(path, durable=durable) as fh:
            fh.write(data)
    except OSError as e:
        raise CaptureError(f"cannot write {path}: {_reason(e)}") from None
    return path


def fit_frame(image: np.ndarray, w: int, h: int) -> np.ndarray:
    """Crop or pad (repeating the edge) to exactly w×h: a video keeps the size it started
    with even if the view is resized while recording; nothing is rescaled."""
    image = image[:h, :w]
    ph, pw = h - image.shape[0], w - image.shape[1]
    if ph or pw:
        image = np.pad(image, ((0, ph), (0, pw), (0, 0)), mode="edge")
    return np.ascontiguousarray(image)


class VideoWriter:
    """Frames in, an MP4 or GIF out (see the module notes on crash safety)."""

    def __init__(self, path: Path, fps: float, size: tuple[int, int]):
        self.path = Path(path)
        self.fps = float(fps)
        self.size = (int(size[0]), int(size[1]))
        self.kind = self.path.suffix.lower()
        if self.kind not in VIDEO_SUFFIXES:
            raise CaptureError(f"{self.path}: unsupported video type; use .mp4 or .gif")
        if not os.access(self.path.parent if str(self.path.parent) else ".", os.W_OK):
            raise CaptureError(f"cannot write {self.path}: folder is not writable")
        self.frames = 0
        self.closed = False
        self._gif: list[np.ndarray] = []
        self._encoder = None
        self.partial: Path | None = None
        if self.kind == ".mp4":
            self.partial = claim_partial(self.path)
            self._start_mp4()

    def _start_mp4(self) -> None:
        import imageio_ffmpeg

        w, h = self.size
        # yuv420p (what every player decodes) needs even sides: pad by one edge pixel rather
        # than rescale, so odd sizes come out 1 px larger, never blurred.
        self.encoded_size = (w + w % 2, h + h % 2)
        gop = str(max(1, round(self.fps)))
        try:
            self._encoder = imageio_ffmpeg.write_frames(
                str(self.partial), self.encoded_size, fps=self.fps, codec="libx264",
                # quiet: ffmpeg's stderr is ours (imageio-ffmpeg does not pipe it); its lines
                # would land under the app's screen or beside our one-line error
                quality=None, macro_block_size=1, ffmpeg_log_level="quiet",
                output_params=[
                    "-crf", "20", "-preset", "veryfast",
                    # No lookahead/B-frames: frames leave x264 at once, not seconds later.
                    "-tune", "zerolatency",
                    "-g", gop,  # a keyframe, hence a fragment, every second
                    "-movflags", "frag_keyframe+empty_moov+default_base_moof",
                    # Write each fragment through to the file now, not when 32 KB pile up.
                    "-flush_packets", "1"])
            self._encoder.send(None)  # starts ffmpeg
        except (OSError, RuntimeError) as e:
            with contextlib.suppress(OSError):
                os.unlink(self.partial)
            raise CaptureError(f"cannot start the video encoder for {self.path}: "
                               f"{_reason(e)}") from None

    def write(self, image: np.ndarray) -> None:
        if self.closed:
            return
        w, h = self.size
        frame = fit_frame(np.asarray(image, dtype=np.uint8), w, h)
        if self.kind == ".gif":
            if self.frames >= gif_max_frames(self.size):
                raise CaptureError(f"{self.path}: a GIF holds every frame in memory: at most "
                                   f"{gif_max_frames(self.size)} frames at {w}x{h}; use .mp4")
            self._gif.append(frame)
        else:
            ew, eh = self.encoded_size
            if (ew, eh) != (w, h):
                frame = fit_frame(frame, ew, eh)
            try:
                self._encoder.send(frame.tobytes())
            except (OSError, RuntimeError, StopIteration) as e:
                self.abort()
                raise CaptureError(f"video encoder failed for {self.path}: "
                                   f"{_encoder_failure(e, self.path.parent)}") from None
        self.frames += 1

    def close(self) -> Path:
        """Finish the file and give it its final name; returns that name."""
        if self.closed:
            return self.path
        self.closed = True
        try:
            if self.kind == ".gif":
                self._write_gif()
            else:
                self._encoder.close()  # ffmpeg writes its last fragment and exits
                os.replace(self.partial, self.path)
        except (OSError, RuntimeError, ValueError) as e:
            self._remove_empty_partial()
            raise CaptureError(f"cannot finish {self.path}: "
                               f"{_encoder_failure(e, self.path.parent)}") from None
        return self.path

    def _write_gif(self) -> None:
        import imageio.v3 as iio

        frames = self._gif or [np.zeros((self.size[1], self.size[0], 3), np.uint8)]
        self._gif = []
        data = iio.imwrite("<bytes>", np.stack(frames), extension=".gif",
                           duration=1000.0 / self.fps, loop=0)
        with atomic_write(self.path) as fh:
            fh.write(data)

    def discard(self) -> None:
        """Stop and remove the file: for a recording with nothing in it."""
        self.abort()
        if self.partial is not None:
            with contextlib.suppress(OSError):
                os.unlink(self.partial)

    def abort(self) -> None:
        """Stop without finishing; an MP4 keeps its playable `.partial.mp4`."""
        if self.closed:
            return
        self.closed = True
        self._gif = []
        if self._encoder is not None:
            with contextlib.suppress(Exception):
                self._encoder.close()
        self._remove_empty_partial()

    def _remove_empty_partial(self) -> None:
        """A partial MP4 with data plays up to its last fragment and stays; an empty one
        (e.g. the disk was full from the start) is only clutter."""
        if self.partial is None:
            return
        with contextlib.suppress(OSError):
            if os.stat(self.partial).st_size == 0:
                os.unlink(self.partial)


class PreviewFile:
    """Keeps FOLDER/preview.png showing the newest frame, at most `rate` times a second, for
    viewers outside the terminal (an image viewer that reloads, a browser)."""

    def __init__(self, folder: Path, rate: float = 5.0):
        self.path = Path(folder) / PREVIEW_NAME
        self.period = 1.0 / rate
        self._last = -1e9
        self.failed = False

    def offer(self, image: np.ndarray, force: bool = False) -> bool:
        """Write if due; returns whether it wrote. Raises CaptureError on the first failure of
        a run of them (a preview is a convenience: one report is enough), then retries every
        PREVIEW_RETRY_S quietly, and writes at its rate again once writing works."""
        now = time.monotonic()
        period = PREVIEW_RETRY_S if self.failed else self.period
        if not force and now - self._last < period:
            return False
        self._last = now
        try:
            # Fast: 5 Hz must stay cheap; no fsync, a preview is worthless after a crash.
            save_png(image, self.path, compress_level=1, durable=False)
        except CaptureError:
            if self.failed:
                return False  # still failing: already reported
            self.failed = True
            raise
        self.failed = False
        return True
