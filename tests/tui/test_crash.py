"""An exception inside the app ends it like any internal error: one line on stderr naming a
log that holds the traceback, exit status 1, and no traceback on the terminal."""

import os
import re
import subprocess
import sys
from pathlib import Path

# The real command line (cli.main → run_app → ClothApp.run), headless, with one method of
# the app broken the way a bug would break it: the status refresh raises. (No GL needed:
# the renderer's probe fails and the app goes on without a preview until the bug strikes.)
SCRIPT = """
import sys
from textual.app import App
from cloth_tui import cli
from cloth_tui.tui import app as tui

run = App.run
tui.ClothApp.run = lambda self, **kw: run(self, headless=True, size=(120, 40))

def broken(self):
    raise RuntimeError("boom in the app")

tui.ClothApp._refresh_status = broken
sys.exit(cli.main(["--captures", sys.argv[1]]))
"""


def test_exception_in_the_app_is_one_line_and_a_log(tmp_path):
    p = subprocess.run([sys.executable, "-c", SCRIPT, str(tmp_path / "caps")],
                       capture_output=True, text=True, timeout=300, cwd=tmp_path,
                       env=dict(os.environ, __EGL_VENDOR_LIBRARY_FILENAMES="/nonexistent.json"))
    assert p.returncode == 1, p.stderr
    lines = p.stderr.strip().splitlines()
    assert len(lines) == 1, p.stderr
    assert "Traceback" not in p.stderr and "Traceback" not in p.stdout
    m = re.fullmatch(r"cloth-tui: internal error: RuntimeError: boom in the app "
                     r"\(traceback in (.+\.log)\)", lines[0])
    assert m, lines[0]
    log = Path(m.group(1))
    try:
        text = log.read_text()
        assert "Traceback" in text and "boom in the app" in text and "broken" in text
    finally:
        log.unlink()
