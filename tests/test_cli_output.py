"""A result that cannot be written (a full device, a closed stdout) is exit 2 and one line on
stderr: never an OSError's traceback, never exit 0 with nothing written."""

import os
import re
import subprocess
import sys

import pytest

PRINTING = [
    ["--version"],
    ["--help"],
    ["scenes"],
    ["simulate", "default", "--frames", "2", "--json"],
    ["simulate", "default", "--frames", "2"],
    ["lab", "catenary", "--resolutions", "8"],
]


def run_with_stdout(args, stdout, **kwargs):
    """(exit status, stderr without the compile notice's lines): a tree whose kernels are
    not in numba's cache yet says it is compiling them, which is not the error."""
    p = subprocess.run([sys.executable, "-m", "cloth_tui", *args], stdout=stdout,
                       stderr=subprocess.PIPE, text=True, timeout=300, **kwargs)
    notice = re.compile(r"cloth-tui: (compiling kernels|\d+ kernels compiled)")
    return p.returncode, "".join(line for line in p.stderr.splitlines(keepends=True)
                                 if not notice.match(line))


@pytest.mark.skipif(not os.path.exists("/dev/full"), reason="needs /dev/full")
@pytest.mark.parametrize("args", PRINTING, ids=" ".join)
def test_a_full_device_is_exit_2_and_one_line(args):
    with open("/dev/full", "w") as full:
        code, err = run_with_stdout(args, full)
    assert code == 2
    assert err == "cloth-tui: error: cannot write to standard output: No space left on device\n"


@pytest.mark.parametrize("args", [["--version"], ["scenes"],
                                  ["simulate", "default", "--frames", "1", "--json"]],
                         ids=" ".join)
def test_a_closed_stdout_is_exit_2_and_one_line(args):
    code, err = run_with_stdout(args, None, preexec_fn=lambda: os.close(1))
    assert (code, err) == (2, "cloth-tui: error: standard output is closed; the result could "
                              "not be written\n")


def test_a_reader_that_has_gone_is_no_error():
    # `cloth-tui lab --help | true`: the reader closes the pipe before the text is written
    child = subprocess.Popen([sys.executable, "-m", "cloth_tui", "lab", "--help"],
                             stdout=subprocess.PIPE, stderr=subprocess.PIPE)
    child.stdout.close()
    err = child.stderr.read()
    assert child.wait(timeout=60) == 0 and err == b""


def test_the_checked_stand_in_is_gone_after_the_command(capsys):
    from cloth_tui.cli import main

    before = sys.stdout
    assert main(["scenes"]) == 0
    assert sys.stdout is before
    assert "default" in capsys.readouterr().out
