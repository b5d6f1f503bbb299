"""`cloth-tui wedge`: the runs' numbers are `simulate`'s, the sheet is written (also partly,
after Ctrl+C), bad input is one line and exit 2."""

import json
import os
import pty
import re
import select
import signal
import subprocess
import sys
import time

import numpy as np
import pytest

from cloth_tui.cli import main

pytest.importorskip("distributed")

TINY = ["--set", "cloth.resolution=8", "--size", "64x48"]


def run(*args, timeout=300):
    p = subprocess.run([sys.executable, "-m", "cloth_tui", *args], capture_output=True,
                       text=True, timeout=timeout)
    return p.returncode, p.stdout, p.stderr


def test_wedge_json_gives_each_run_the_numbers_simulate_gives(tmp_path):
    out = tmp_path / "w.png"
    rc, text, err = run("wedge", "default", *TINY, "--vary", "forces.wind=true",
                        "--vary", "forces.wind_strength=2,8", "--frames", "12", "-o", str(out),
                        "--json", "--workers", "1")
    assert rc == 0, err
    r = json.loads(text)
    assert r["complete"] and r["frames"] == 12 and len(r["runs"]) == 2
    assert r["vary"] == {"forces.wind": [True], "forces.wind_strength": [2.0, 8.0]}
    for run_ in r["runs"]:
        for k in ("max_stretch", "energy_drift", "penetration", "recoveries", "substeps_used",
                  "wall_s"):
            assert run_[k] is not None
        rc, s, err = run("simulate", "default", "--set", "cloth.resolution=8", "--set",
                         "forces.wind=true", "--set",
                         f"forces.wind_strength={run_['values']['forces.wind_strength']}",
                         "--frames", "12", "--json")
        sim = json.loads(s)
        assert run_["max_stretch"] == sim["max_stretch"]
        assert run_["substeps_used"] == sim["substeps_used"]
    assert r["runs"][0]["max_stretch"] != r["runs"][1]["max_stretch"]
    import imageio.v3 as iio
    img = iio.imread(out)
    assert img.shape[1] > 2 * 64 and img.shape[0] > 48  # two thumbnails side by side, labels
    assert not list(tmp_path.glob("*.tmp*"))


def test_wedge_video_is_an_mp4_grid_with_sides_multiple_of_16(tmp_path):
    import imageio_ffmpeg
    out = tmp_path / "w.mp4"
    rc, text, err = run("wedge", "default", *TINY, "--vary", "scene.friction=0,1",
                        "--frames", "6", "--video", "-o", str(out), "--workers", "1")
    assert rc == 0, err
    assert "2 of 2 runs" in text
    reader = imageio_ffmpeg.read_frames(str(out))
    meta = next(reader)
    w, h = meta["size"]
    assert w % 16 == 0 and h % 16 == 0
    assert sum(1 for _ in reader) == 6


def test_ctrl_c_keeps_the_runs_done_and_writes_the_partial_sheet(tmp_path):
    """SIGINT to the command (workers untouched) once progress shows a finished run."""
    out = tmp_path / "w.png"
    master, slave = pty.openpty()  # stderr a terminal: the progress bar is shown
    p = subprocess.Popen([sys.executable, "-m", "cloth_tui", "wedge", "default", *TINY,
                          "--vary", "forces.wind_strength=0,1,2,3,4,5,6,7", "--frames", "150",
                          "-o", str(out), "--json", "--workers", "1"],
                         stdout=subprocess.PIPE, stderr=slave, text=True)
    os.close(slave)
    # a finished run on the wedge's own bar, not the check of the runs that comes before it
    done = re.compile(rb"wedge \[[#.]*\] [1-8]/8")
    seen, deadline = b"", time.monotonic() + 240
    while not done.search(seen) and time.monotonic() < deadline and p.poll() is None:
        if select.select([master], [], [], 1.0)[0]:
            try:
                seen += os.read(master, 4096)
            except OSError:
                break
    assert done.search(seen), seen
    p.send_signal(signal.SIGINT)
    text, _ = p.communicate(timeout=120)
    while select.select([master], [], [], 0.2)[0]:
        try:
            chunk = os.read(master, 4096)
        except OSError:
            break
        if not chunk:
            break
        seen += chunk
    os.close(master)
    assert p.returncode == 130, seen
    r = json.loads(text)
    status = [x["status"] for x in r["runs"]]
    assert not r["complete"] and "done" in status and "cancelled" in status
    assert out.exists()
    assert b"partial sheet written" in seen and b"Traceback" not in seen


@pytest.mark.parametrize("argv, words", [
    (["--vary", "forces.wind_strength=2,x"], "forces.wind_strength"),
    (["--vary", "nope.key=1"], "unknown key"),
    (["--vary", "scene.friction=0,1", "--video"], "use a .mp4"),
    (["--vary", "scene.friction=0,1", "--workers", "2", "--scheduler", "tcp://x:1"],
     "not allowed with"),
])
def test_bad_input_is_one_line_and_exit_2(tmp_path, capsys, argv, words):
    rc = main(["wedge", "default", "-o", str(tmp_path / "w.png"), *argv])
    err = capsys.readouterr().err
    assert rc == 2 and words in err and err.count("\n") == 1
    assert not (tmp_path / "w.png").exists()


def test_a_video_wedge_too_big_to_hold_is_refused_up_front(tmp_path, capsys):
    rc = main(["wedge", "default", "--vary", "forces.wind_strength=0,1,2,3", "--video",
               "--frames", "2000", "--size", "640x480", "-o", str(tmp_path / "w.mp4")])
    err = capsys.readouterr().err
    assert rc == 2 and "--video" in err and "MB" in err and err.count("\n") == 1


def test_without_the_extra_the_line_names_it(tmp_path, capsys, monkeypatch):
    monkeypatch.setitem(sys.modules, "distributed", None)  # import distributed → ImportError
    rc = main(["wedge", "default", "--vary", "scene.friction=0,1", "-o", str(tmp_path / "w.png")])
    err = capsys.readouterr().err
    assert rc == 2 and "[wedge]" in err and err.count("\n") == 1
    rc = main(["accuracy", "--quick", "--workers", "2"])
    err = capsys.readouterr().err
    assert rc == 2 and "[wedge]" in err


def test_an_unreachable_scheduler_is_one_line(tmp_path, capsys):
    rc = main(["wedge", "default", *TINY, "--vary", "scene.friction=0,1", "-o",
               str(tmp_path / "w.png"), "--scheduler", "tcp://127.0.0.1:9"])
    err = capsys.readouterr().err
    assert rc == 2 and "cannot connect" in err and err.count("\n") == 1


def test_help_loads_no_dask():
    code = ("import sys, cloth_tui.cli_args as c; c.build_parsers(); "
            "print('distributed' in sys.modules)")
    out = subprocess.run([sys.executable, "-c", code], capture_output=True, text=True)
    assert out.stdout.strip() == "False", out.stderr


def test_table_lists_every_run_with_its_status():
    from cloth_tui.wedge.cli import format_table
    rows = [{"values": {"scene.friction": 0.0}, "status": "done", "max_stretch": 0.012,
             "energy_drift": -0.5, "penetration": 0.0, "recoveries": 1, "substeps_used": 8,
             "wall_s": 0.25, "halted": None},
            {"values": {"scene.friction": 1.0}, "status": "cancelled"}]
    text = format_table(rows, ["scene.friction"]).splitlines()
    assert len(text) == 3 and "1.20" in text[1] and "cancelled" in text[2]
    assert np.all([len(line) == len(text[0]) for line in text])


@pytest.fixture
def silent_server():
    """A server that accepts connections and never says a word (nor closes them)."""
    import socket
    import threading

    server = socket.create_server(("127.0.0.1", 0))
    held = []
    stop, accepted = threading.Event(), threading.Event()

    def accept():
        server.settimeout(0.2)
        while not stop.is_set():
            try:
                held.append(server.accept()[0])
                accepted.set()
            except OSError:
                continue

    thread = threading.Thread(target=accept, daemon=True)
    thread.start()
    yield f"tcp://127.0.0.1:{server.getsockname()[1]}", accepted
    stop.set()
    thread.join()
    for conn in held:
        conn.close()
    server.close()


def _wedge_on(address, tmp_path):
    return subprocess.Popen([sys.executable, "-m", "cloth_tui", "wedge", "default", *TINY,
                             "--vary", "scene.friction=0,1", "-o", str(tmp_path / "w.png"),
                             "--scheduler", address], stdout=subprocess.PIPE,
                            stderr=subprocess.PIPE, text=True)


def test_a_scheduler_that_accepts_and_never_answers_times_out_in_one_line(tmp_path,
                                                                          silent_server):
    proc = _wedge_on(silent_server[0], tmp_path)
    try:
        _, err = proc.communicate(timeout=90)
    finally:
        proc.kill()
    assert proc.returncode == 2 and err.count("\n") == 1, err
    assert "said nothing in 10 s" in err


@pytest.mark.parametrize("sig, status", [(signal.SIGTERM, 143), (signal.SIGINT, 130)])
def test_signals_end_the_wait_for_a_silent_scheduler(tmp_path, silent_server, sig, status):
    address, accepted = silent_server
    proc = _wedge_on(address, tmp_path)
    try:
        assert accepted.wait(60), "the wedge never connected"
        time.sleep(1)  # connected and waiting for a word (for 10 s)
        proc.send_signal(sig)
        _, err = proc.communicate(timeout=30)
    finally:
        proc.kill()
    assert proc.returncode == status and "stopped after 0 of 2 runs" in err, err
    assert err.count("\n") == 1


def test_workers_beyond_the_bound_are_refused_before_any_work(tmp_path, capsys):
    from cloth_tui.wedge.engine import max_workers

    rc = main(["wedge", "default", *TINY, "--vary", "scene.friction=0,1", "-o",
               str(tmp_path / "w.png"), "--workers", "100000"])
    err = capsys.readouterr().err
    assert rc == 2 and err.count("\n") == 1
    assert f"--workers 100000: at most {max_workers()}" in err
    assert not (tmp_path / "w.png").exists()


def test_no_more_workers_start_than_there_are_runs():
    from cloth_tui.wedge.engine import max_workers, worker_count

    assert worker_count(max_workers(), 2) == 2
    assert worker_count(1, 5) == 1
    assert 1 <= worker_count(None, 3) <= 3


def test_a_run_simulate_refuses_is_one_line_before_any_worker_starts(tmp_path, capsys,
                                                                     monkeypatch):
    # The scene's keys are each valid; only the simulation's set-up finds the sphere
    # enclosing a held corner once the sheet is lowered into it.
    import cloth_tui.wedge.cli as wedge_cli

    def no_cluster(*_args, **_kwargs):
        raise AssertionError("a cluster started")

    monkeypatch.setattr(wedge_cli, "Engine", no_cluster)
    monkeypatch.setattr(wedge_cli, "require_dask", no_cluster)
    code = main(["wedge", "sphere", "--set", "cloth.pinned=corners", "--set", "cloth.size=0.2",
                 "--vary", "cloth.height=0,-0.3", "-o", str(tmp_path / "sheet.png")])
    err = capsys.readouterr().err
    assert code == 2 and err.count("\n") == 1
    assert err.startswith("cloth-tui: error: --vary: the run cloth.height=-0.3 is refused: ")
    assert "encloses a held particle" in err
    assert main(["simulate", "sphere", "--set", "cloth.pinned=corners", "--set",
                 "cloth.size=0.2", "--set", "cloth.height=-0.3"]) == 2  # as simulate says
