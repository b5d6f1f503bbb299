import os
import shutil
import signal
import subprocess
import sys
import time

import pytest

from cloth_tui.cli import main

from .service_helpers import count_frames


def test_png_of_any_size(tmp_path):
    import imageio.v3 as iio
    out = tmp_path / "a.png"
    assert main(["render", "default", "-o", str(out), "--size", "81x61"]) == 0
    assert iio.imread(out).shape == (61, 81, 3)


def test_mp4_has_every_frame(tmp_path):
    out = tmp_path / "a.mp4"
    assert main(["render", "default", "-o", str(out), "--frames", "12", "--size", "65x49",
                 "--set", "appearance.auto_rotate=true"]) == 0
    assert count_frames(out) == 12
    assert not (tmp_path / "a.partial.mp4").exists()


@pytest.mark.parametrize("args", [["--size", "12"], ["--size", "0x10"], ["--size", "axb"],
                                  ["-o", "x.bmp"], ["-o", "/no/such/folder/x.png"]])
def test_bad_input_is_one_line_exit_2(tmp_path, capsys, args):
    base = ["render", "default", "-o", str(tmp_path / "x.png")]
    assert main(base + args) == 2
    err = capsys.readouterr().err
    assert err.count("\n") == 1 and "error" in err


def test_folder_that_refuses_files_is_bad_input_exit_2(capsys):
    """/sys refuses new files even to root, whom os.access says yes to."""
    assert main(["render", "default", "-o", "/sys/x.png"]) == 2
    err = capsys.readouterr().err
    assert err.count("\n") == 1 and "Permission denied" in err


def test_output_inside_a_file_says_it_is_not_a_folder(tmp_path, capsys):
    (tmp_path / "somefile").write_text("x")
    assert main(["render", "default", "-o", str(tmp_path / "somefile" / "x.png")]) == 2
    err = capsys.readouterr().err
    assert err.count("\n") == 1 and "somefile is not a folder" in err
    assert "does not exist" not in err


def test_png_defaults_to_two_simulated_seconds(tmp_path, monkeypatch):
    """A PNG shows the settled sheet: 2 s of simulated time, whatever the frame rate."""
    from cloth_tui.sim.run.runner import Simulation
    calls = []
    advance = Simulation.advance_frame
    monkeypatch.setattr(Simulation, "advance_frame",
                        lambda self, *a, **k: calls.append(1) or advance(self, *a, **k))
    out = tmp_path / "a.png"
    assert main(["render", "default", "-o", str(out), "--size", "32x24",
                 "--set", "behavior.frame_rate=30"]) == 0
    assert len(calls) == 60 and out.is_file()


def test_render_cli_takes_no_helpers_and_imports_no_cli():
    """The render and accuracy commands import what they need; cli.py imports them lazily,
    never the other way round."""
    import inspect

    from cloth_tui.render.cli import run_render
    assert list(inspect.signature(run_render).parameters) == ["args"]
    code = ("import sys, cloth_tui.render.cli, cloth_tui.bench.accuracy_cli, "
            "cloth_tui.bench.cli; print('cloth_tui.cli' in sys.modules)")
    out = subprocess.run([sys.executable, "-c", code], capture_output=True, text=True,
                         timeout=120)
    assert out.returncode == 0, out.stderr
    assert out.stdout.strip() == "False"


def _start(tmp_path, name):
    """A long render in a child process, at 10 fps so a fragment completes every 10 frames."""
    out = tmp_path / name
    env = dict(os.environ, PYTHONUNBUFFERED="1")
    proc = subprocess.Popen([sys.executable, "-m", "cloth_tui", "render", "default", "-o",
                             str(out), "--frames", "100000", "--fps", "10", "--size", "96x72"],
                            stdout=subprocess.DEVNULL, stderr=subprocess.PIPE, env=env)
    return proc, out, out.with_name(out.stem + ".partial.mp4")


def _wait_for_frames(proc, partial, tmp_path, minimum=1, timeout=60.0):
    deadline = time.monotonic() + timeout
    copy = tmp_path / "peek.mp4"
    while time.monotonic() < deadline and proc.poll() is None:
        if partial.exists() and partial.stat().st_size > 1000:
            shutil.copy(partial, copy)
            try:
                if count_frames(copy) >= minimum:
                    return
            except Exception:
                pass
        time.sleep(0.3)
    proc.kill()
    pytest.fail(f"no playable frames appeared in {partial}")


def test_sigkill_leaves_a_playable_partial_mp4(tmp_path):
    proc, out, partial = _start(tmp_path, "killed.mp4")
    _wait_for_frames(proc, partial, tmp_path, minimum=10)
    proc.send_signal(signal.SIGKILL)
    proc.wait(10)
    time.sleep(0.5)  # ffmpeg sees the pipe close and exits
    assert not out.exists() and partial.exists()
    assert count_frames(partial) > 0


@pytest.mark.parametrize("sig,status", [(signal.SIGINT, 130), (signal.SIGTERM, 143)])
def test_interrupt_finishes_the_video(tmp_path, sig, status):
    proc, out, partial = _start(tmp_path, "stopped.mp4")
    _wait_for_frames(proc, partial, tmp_path)
    proc.send_signal(sig)
    _, err = proc.communicate(timeout=30)
    assert proc.returncode == status
    assert err.decode().strip().count("\n") == 0 and "saved" in err.decode()
    assert out.exists() and not partial.exists()
    assert count_frames(out) > 0
