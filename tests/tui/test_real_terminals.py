"""The app in real terminals under Xvfb: kitty (kitty graphics) and `xterm -ti vt340` (sixel).

Each terminal runs `cloth-tui` at 160×48 cells with auto-rotate on; two screenshots of the X
display (ImageMagick `import`) two seconds apart must show, in the preview's part of the
window, a true-pixel picture (many colours, and detail inside cells: a half-block cell has
two colours) that moves. Frames per second come from the app's debug log (frames shown).
Slow (about a minute each); skipped where Xvfb, the terminal or `import` is missing.
"""

from __future__ import annotations

import os
import shutil
import signal
import subprocess
import sys
import time
from pathlib import Path

import numpy as np
import pytest
from PIL import Image

ROOT = Path(__file__).resolve().parents[2]
COLS, ROWS = 160, 48
SCREEN = (1920, 1200)

pytestmark = pytest.mark.slow


def _free_display() -> int:
    for n in range(70, 99):
        if not Path(f"/tmp/.X11-unix/X{n}").exists() and not Path(f"/tmp/.X{n}-lock").exists():
            return n
    pytest.skip("no free X display number")


@pytest.fixture
def display():
    if not shutil.which("Xvfb") or not shutil.which("import"):
        pytest.skip("Xvfb or ImageMagick import missing")
    n = _free_display()
    xvfb = subprocess.Popen(["Xvfb", f":{n}", "-screen", "0", f"{SCREEN[0]}x{SCREEN[1]}x24"],
                            stdout=subprocess.DEVNULL, stderr=subprocess.DEVNULL)
    deadline = time.monotonic() + 10
    while not Path(f"/tmp/.X11-unix/X{n}").exists():
        if time.monotonic() > deadline or xvfb.poll() is not None:
            xvfb.kill()
            pytest.skip("Xvfb did not start")
        time.sleep(0.1)
    yield f":{n}"
    xvfb.terminate()
    xvfb.wait(5)


def screenshot(display: str, path: Path) -> np.ndarray:
    keep = os.environ.get("CLOTH_TUI_SHOT_DIR")  # to look at them after pytest cleans up
    if keep:
        path = Path(keep) / path.name
    subprocess.run(["import", "-display", display, "-window", "root", f"PNG24:{path}"],
                   check=True, timeout=30)
    return np.asarray(Image.open(path).convert("RGB"))


def window_box(shot: np.ndarray) -> tuple[int, int, int, int]:
    """(x0, y0, x1, y1) of the terminal window: what is not the root's black."""
    lit = shot.max(axis=-1) > 0
    ys, xs = np.flatnonzero(lit.any(axis=1)), np.flatnonzero(lit.any(axis=0))
    return xs[0], ys[0], xs[-1] + 1, ys[-1] + 1


def picture_measures(shot: np.ndarray, box) -> tuple[int, float, np.ndarray]:
    """(distinct colours in the preview area, fraction of its cells holding more than 3
    colours, the area). A half-block cell shows two colours; a picture in pixels shows
    more in most cells (shading, edges, sixel's dither). Distinct colours are few in a
    dithered sixel picture (a fixed palette), so they only tell a picture from blank cells. The preview is the left of the window above the status line:
    its left half and top three quarters are inside it at 160×48 whatever the controls."""
    x0, y0, x1, y1 = box
    cw, ch = (x1 - x0) / COLS, (y1 - y0) / ROWS
    area = shot[y0:y0 + int(0.75 * (y1 - y0)), x0:x0 + int(0.5 * (x1 - x0))]
    packed = (area[..., 0].astype(np.int64) << 16) | (area[..., 1].astype(np.int64) << 8) \
        | area[..., 2]
    colours = len(np.unique(packed))
    rich = total = 0
    for r in range(int(area.shape[0] // ch)):
        for c in range(int(area.shape[1] // cw)):
            cell = packed[int(r * ch):int((r + 1) * ch), int(c * cw):int((c + 1) * cw)]
            total += 1
            rich += len(np.unique(cell)) > 3
    return colours, rich / max(total, 1), area


def ui_ms(log: Path) -> float:
    """Median time the UI thread spent handing a frame to the preview (the debug log's)."""
    values = [float(line.split("ui_ms ")[1]) for line in log.read_text().splitlines()
              if "ui_ms " in line]
    return float(np.median(values)) if values else float("nan")


def frame_times(log: Path) -> list[float]:
    if not log.exists():
        return []
    return [float(line.split()[0]) for line in log.read_text().splitlines()
            if " frame " in line]


TERMINALS = {
    "kitty": ["kitty", "-o", "remember_window_size=no", "-o", f"initial_window_width={COLS}c",
              "-o", f"initial_window_height={ROWS}c", "-o", "placement_strategy=top-left"],
    "sixel": ["xterm", "-ti", "vt340", "-geometry", f"{COLS}x{ROWS}+0+0", "-fa", "Monospace",
              "-fs", "9", "-e"],
}


@pytest.mark.parametrize("mode", ["kitty", "sixel"])
def test_true_pixels_in_a_real_terminal(display, tmp_path, mode):
    terminal = TERMINALS[mode]
    if not shutil.which(terminal[0]):
        pytest.skip(f"{terminal[0]} missing")
    log = tmp_path / "debug.log"
    env = dict(os.environ, DISPLAY=display, PYTHONPATH=str(ROOT), CLOTH_TUI_DEBUG_LOG=str(log))
    env.pop("COLORTERM", None)
    env.pop("TMUX", None)
    app = [sys.executable, "-m", "cloth_tui", "--captures", str(tmp_path / "caps"),
           "--set", "appearance.auto_rotate=true"]
    term = subprocess.Popen(terminal + app, env=env, cwd=tmp_path, start_new_session=True,
                            stdout=subprocess.DEVNULL, stderr=subprocess.DEVNULL)
    try:
        deadline = time.monotonic() + 90
        while len(frame_times(log)) < 10:  # start-up, numba cache, the first frames
            if time.monotonic() > deadline or term.poll() is not None:
                pytest.fail(f"no frames in {mode} (terminal exit {term.poll()})")
            time.sleep(0.5)
        time.sleep(2)
        first = screenshot(display, tmp_path / f"{mode}-1.png")
        n0, t0 = len(frame_times(log)), time.monotonic()
        time.sleep(3)
        second = screenshot(display, tmp_path / f"{mode}-2.png")
        fps = (len(frame_times(log)) - n0) / (time.monotonic() - t0)
    finally:
        os.killpg(term.pid, signal.SIGTERM)
        try:
            term.wait(10)
        except subprocess.TimeoutExpired:
            os.killpg(term.pid, signal.SIGKILL)
    box = window_box(first)
    colours, rich_cells, area1 = picture_measures(first, box)
    _, _, area2 = picture_measures(second, box)
    changed = (np.abs(area1.astype(int) - area2.astype(int)).max(axis=-1) > 16).mean()
    print(f"{mode}: {fps:.1f} frames/s shown (UI {ui_ms(log):.2f} ms a frame), {colours} colours, {rich_cells:.0%} cells with "
          f"detail, {changed:.0%} of the preview changed; {tmp_path}")
    assert colours >= 20, "the preview area holds no picture"
    assert rich_cells > 0.3, "no detail finer than a cell"
    assert changed > 0.01, "the picture did not move"
