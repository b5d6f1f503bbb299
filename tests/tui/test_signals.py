"""SIGTERM and SIGHUP while the app records end it as `q` does: the video is finished (an
.mp4 that reads, no .partial.mp4 left) and the terminal is restored (alternate screen off,
mouse tracking off, cursor shown). The real app, in a pseudo-terminal, with the real renderer;
skipped where the renderer cannot start."""

import os
import pty
import signal
import subprocess
import sys
import threading
import time

import pytest

from cloth_tui.render.probe import RendererUnavailable, require_renderer

SCRIPT = "import sys; from cloth_tui import cli; sys.exit(cli.main(['--captures', sys.argv[1]]))"


def _wait(condition, timeout: float, what: str) -> None:
    deadline = time.monotonic() + timeout
    while not condition():
        assert time.monotonic() < deadline, f"timed out waiting for {what}"
        time.sleep(0.1)


@pytest.mark.parametrize("sig", [signal.SIGTERM, signal.SIGHUP])
def test_signal_while_recording_finishes_video_and_restores_terminal(tmp_path, sig):
    try:
        require_renderer()
    except RendererUnavailable as e:
        pytest.skip(f"renderer unavailable: {e}")
    iio = pytest.importorskip("imageio.v3")
    caps = tmp_path / "caps"
    master, slave = pty.openpty()
    os.set_blocking(master, True)
    env = dict(os.environ, TERM="xterm-256color", COLUMNS="120", LINES="40")
    child = subprocess.Popen([sys.executable, "-c", SCRIPT, str(caps)], stdin=slave,
                             stdout=slave, stderr=slave, env=env, cwd=tmp_path,
                             start_new_session=True)
    os.close(slave)
    out = bytearray()

    def read() -> None:  # keep draining, or the app blocks writing to the terminal
        while True:
            try:
                chunk = os.read(master, 65536)
            except OSError:
                return
            if not chunk:
                return
            out.extend(chunk)

    reader = threading.Thread(target=read, daemon=True)
    reader.start()
    try:
        _wait(lambda: (caps / "preview.png").exists(), 90, "the first picture")
        os.write(master, b"v")
        _wait(lambda: any(p.stat().st_size > 0 for p in caps.glob("*.partial.mp4")), 30,
              "the recording")
        time.sleep(1.5)  # a second of video
        child.send_signal(sig)
        assert child.wait(timeout=30) == 128 + sig
    finally:
        if child.poll() is None:
            child.kill()
            child.wait()
        reader.join(5)
        os.close(master)
    assert not list(caps.glob("*.partial.mp4"))
    videos = list(caps.glob("*.mp4"))
    assert len(videos) == 1
    assert len(iio.imread(videos[0])) > 0
    tail = bytes(out).rsplit(b"\x1b[?1049h", 1)[-1]  # after entering the alternate screen
    assert b"\x1b[?1049l" in tail, "still in the alternate screen"
    assert b"\x1b[?1000l" in tail, "mouse tracking left on"
    assert b"\x1b[?25h" in tail, "cursor left hidden"


@pytest.mark.heavy
def test_sighup_from_a_terminal_that_stopped_reading_still_ends_the_app(tmp_path):
    """A killed terminal window: it stops reading (the pseudo-terminal's buffer fills and
    Textual's output queue with it), then SIGHUP comes and the terminal is gone. Textual's own
    shutdown then waits on that queue forever; the app must still leave (exit 128 + SIGHUP)
    once its captures are saved, not stay behind as an orphan process."""
    try:
        require_renderer()
    except RendererUnavailable as e:
        pytest.skip(f"renderer unavailable: {e}")
    from cloth_tui.tui.process import EXIT_GRACE_S

    caps = tmp_path / "caps"
    master, slave = pty.openpty()
    env = dict(os.environ, TERM="xterm-256color", COLUMNS="160", LINES="48")
    child = subprocess.Popen([sys.executable, "-c", SCRIPT, str(caps)], stdin=slave,
                             stdout=slave, stderr=slave, env=env, cwd=tmp_path,
                             start_new_session=True)
    os.close(slave)
    reading = threading.Event()
    reading.set()

    def read() -> None:
        while reading.is_set():
            try:
                if not os.read(master, 65536):
                    return
            except OSError:
                return

    reader = threading.Thread(target=read, daemon=True)
    reader.start()
    try:
        _wait(lambda: (caps / "preview.png").exists(), 90, "the first picture")
        reading.clear()  # the window freezes: nobody reads the terminal any more
        time.sleep(5)
        child.send_signal(signal.SIGHUP)
        os.close(master)  # and is gone
        master = None
        assert child.wait(timeout=EXIT_GRACE_S + 20) == 128 + signal.SIGHUP
    finally:
        if child.poll() is None:
            child.kill()
            child.wait()
        if master is not None:
            os.close(master)
