"""Ctrl+C at any moment after Python has started the command: exit 130 and one line, never a
traceback, whether it lands while modules load, inside a library that turns it into an error
of its own, in the middle of the work, or in the interpreter's shutdown.

The moments are events, not delays: the child sends itself SIGINT when a chosen module starts
to load (or at exit), or the test sends it once /proc shows a library mapped."""

import os
import signal
import subprocess
import sys
import time

import pytest

# The console script's own two lines (`from cloth_tui.cli import main; sys.exit(main())`),
# after a finder that sends SIGINT to this process when module `target` is first looked for.
CHILD = """
import atexit, os, signal, sys
target, marker = sys.argv[1], sys.argv[2]

def trip():
    open(marker, "w").close()
    os.kill(os.getpid(), signal.SIGINT)

class Trip:
    def find_spec(self, name, path=None, module=None):
        if name == target:
            sys.meta_path.remove(self)
            trip()
        return None

if target == "<exit>":
    atexit.register(trip)
else:
    sys.meta_path.insert(0, Trip())
sys.argv = ["cloth-tui", *sys.argv[3:]]
from cloth_tui.cli import main
sys.exit(main())
"""


def run_tripped(tmp_path, target, *args):
    marker = tmp_path / "tripped"
    p = subprocess.run([sys.executable, "-c", CHILD, target, str(marker), *args],
                       capture_output=True, text=True, timeout=300, cwd=tmp_path)
    assert marker.exists(), f"{target} was never loaded: the test did not interrupt anything"
    return p


@pytest.mark.parametrize("target, args", [
    ("cloth_tui.cli_args", ["scenes"]),                      # the parsers load
    ("cloth_tui.resources", ["scenes"]),
    ("numpy", ["simulate", "default", "--frames", "1"]),
    ("numba", ["simulate", "default", "--frames", "1"]),
    ("cloth_tui.sim.run.runner", ["simulate", "default", "--frames", "1"]),
    # NumPy's C extension loads datetime itself and reports its failure as an ImportError
    ("datetime", ["lab", "catenary", "--resolutions", "8"]),
    ("cloth_tui.bench.step_bench", ["bench", "--quick", "--no-render", "--no-cost"]),
    ("cloth_tui.render.renderer", ["render", "default", "-o", "out.png", "--frames", "1"]),
    ("cloth_tui.wedge.plan", ["wedge", "default", "--vary", "scene.friction=0,1",
                              "-o", "sheet.png"]),
    ("textual", ["default"]),                                # the app, before it starts
])
def test_ctrl_c_while_modules_load_is_one_line_and_130(tmp_path, target, args):
    p = run_tripped(tmp_path, target, *args)
    assert (p.returncode, p.stderr) == (130, "cloth-tui: interrupted\n")


def test_ctrl_c_in_the_shutdown_after_the_work_is_one_line_and_130(tmp_path):
    p = run_tripped(tmp_path, "<exit>", "scenes")
    assert "default" in p.stdout  # the work was done and its output kept
    assert (p.returncode, p.stderr) == (130, "cloth-tui: interrupted\n")


def _mapped(pid: int, library: str) -> bool:
    try:
        with open(f"/proc/{pid}/maps") as fh:
            return library in fh.read()
    except OSError:
        return False


@pytest.mark.skipif(not os.path.exists("/proc/self/maps"), reason="needs /proc")
@pytest.mark.parametrize("library", ["_multiarray_umath", "llvmlite"])
def test_ctrl_c_from_outside_as_a_library_loads(tmp_path, library):
    # the real entry point and a real external signal, sent once the library is mapped
    child = subprocess.Popen([sys.executable, "-m", "cloth_tui", "simulate", "default",
                              "--frames", "400"], stdout=subprocess.DEVNULL,
                             stderr=subprocess.PIPE, text=True, cwd=tmp_path)
    try:
        while not _mapped(child.pid, library) and child.poll() is None:
            time.sleep(0.001)
        assert child.poll() is None, "the command ended before the library loaded"
        child.send_signal(signal.SIGINT)
        _, err = child.communicate(timeout=120)
    finally:
        child.kill()
        child.wait()
    assert (child.returncode, err) == (130, "cloth-tui: interrupted\n")
