"""The app in real terminals under Xvfb: kitty (kitty graphics) and `xterm -ti vt340` (sixel).

Each terminal runs `cloth-tui` at 160×48 cells with auto-rotate on, with its own background
set to a colour nothing in the app draws (so wherever it shows, the app left cells or pixels
unpainted), and is driven with keys (xdotool). Screenshots of the X display (ImageMagick
`import`) are judged as a person would look at them: a picture is where many colours are
and pixels change from one second to the next (the camera orbits); controls are where
pixels stay put. A sixel picture is dithered to a fixed palette, so per-cell colours cannot
tell it from half-blocks; a moving picture versus still text can. Where the regions are
comes from the cell grid (the window's pixels over its cells) and the layout's rules
(status line and footer at the bottom, the drawer's 46 columns, notices above the footer
at the right), never from the app's own account of where it drew.

Slow (one to two minutes each); skipped where Xvfb, the terminal, `import` or xdotool is
missing.
"""

from __future__ import annotations

import math
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

from cloth_tui.tui.pixel_preview import render_size

ROOT = Path(__file__).resolve().parents[2]
COLS, ROWS = 160, 48
NARROW = (100, 30)            # cells after the resize: the controls become a drawer
BELOW_PREVIEW = 3             # the status line's two rows and the footer
DRAWER_COLS = 46
FOOTER_KEYS_COLS = 60         # the footer's key labels from the left, the same at any width
SCREEN = (1920, 1200)
TERMINAL_BG = (0x12, 0x34, 0x56)  # the terminals' own background: no theme or cube colour
STILL = 0.005     # at most this fraction of a region's pixels change where nothing moves
MOVING = 0.01     # at least this fraction changes in a picture while the camera orbits

pytestmark = pytest.mark.slow


def _free_display() -> int:
    for n in range(70, 99):
        if not Path(f"/tmp/.X11-unix/X{n}").exists() and not Path(f"/tmp/.X{n}-lock").exists():
            return n
    pytest.skip("no free X display number")


@pytest.fixture
def display():
    if not shutil.which("Xvfb") or not shutil.which("import") or not shutil.which("xdotool"):
        pytest.skip("Xvfb, ImageMagick import or xdotool missing")
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


def hex_colour(rgb) -> str:
    return "#%02x%02x%02x" % tuple(rgb)


TERMINALS = {
    "kitty": ["kitty", "-o", "remember_window_size=no", "-o", f"initial_window_width={COLS}c",
              "-o", f"initial_window_height={ROWS}c", "-o", "placement_strategy=top-left",
              "-o", "window_padding_width=0", "-o", f"background={hex_colour(TERMINAL_BG)}"],
    "sixel": ["xterm", "-ti", "vt340", "-geometry", f"{COLS}x{ROWS}+0+0", "-b", "0",
              "-fa", "Monospace", "-fs", "9", "-bg", hex_colour(TERMINAL_BG), "-e"],
}


def frame_times(log: Path) -> list[float]:
    if not log.exists():
        return []
    return [float(line.split()[0]) for line in log.read_text().splitlines()
            if " frame " in line]


def ui_ms(log: Path) -> float:
    """Median time the UI thread spent handing a frame to the preview (the debug log's)."""
    values = [float(line.split("ui_ms ")[1]) for line in log.read_text().splitlines()
              if "ui_ms " in line]
    return float(np.median(values)) if values else float("nan")


class Terminal:
    """The app in a real terminal window: keys in, screenshots out, cells to pixels."""

    def __init__(self, mode: str, display: str, tmp_path: Path):
        self.mode, self.display, self.tmp = mode, display, tmp_path
        self.log = tmp_path / "debug.log"
        self.shots = 0
        env = dict(os.environ, DISPLAY=display, PYTHONPATH=str(ROOT),
                   CLOTH_TUI_DEBUG_LOG=str(self.log))
        env.pop("COLORTERM", None)
        env.pop("TMUX", None)
        app = [sys.executable, "-m", "cloth_tui", "--captures", str(tmp_path / "caps"),
               "--set", "appearance.auto_rotate=true"]
        self.proc = subprocess.Popen(TERMINALS[mode] + app, env=env, cwd=tmp_path,
                                     start_new_session=True, stdout=subprocess.DEVNULL,
                                     stderr=subprocess.DEVNULL)
        self.window = ""
        self.origin = (0, 0)
        self.cell = (0, 0)

    def close(self) -> None:
        os.killpg(self.proc.pid, signal.SIGTERM)
        try:
            self.proc.wait(10)
        except subprocess.TimeoutExpired:
            os.killpg(self.proc.pid, signal.SIGKILL)

    def xdotool(self, *args: str) -> str:
        return subprocess.run(["xdotool", *args], env=dict(os.environ, DISPLAY=self.display),
                              capture_output=True, text=True, timeout=30).stdout

    def wait_frames(self, n: int, timeout: float = 90, since: int | None = None) -> None:
        """Until `n` more frames than `since` (default: now) reached the preview (the app
        is up and drawing)."""
        target = (len(frame_times(self.log)) if since is None else since) + n
        deadline = time.monotonic() + timeout
        while len(frame_times(self.log)) < target:
            if time.monotonic() > deadline or self.proc.poll() is not None:
                pytest.fail(f"no frames in {self.mode} (terminal exit {self.proc.poll()})")
            time.sleep(0.3)

    def start(self) -> None:
        self.wait_frames(10)  # start-up, numba cache, the first frames
        ids = self.xdotool("search", "--class", TERMINALS[self.mode][0]).split()
        assert ids, "the terminal's window was not found"
        self.window = ids[-1]
        self.xdotool("windowfocus", "--sync", self.window)
        x0, y0, x1, y1 = window_box(self.shot("start"))
        cw, ch = (x1 - x0) / COLS, (y1 - y0) / ROWS
        assert abs(cw - round(cw)) < 0.05 and abs(ch - round(ch)) < 0.05, (cw, ch)
        self.origin, self.cell = (x0, y0), (round(cw), round(ch))

    def key(self, *keys: str, settle: float = 2.0, frames: int = 2) -> None:
        """Press keys, then let the app act on them and draw again."""
        before = len(frame_times(self.log))
        self.press(*keys)
        time.sleep(settle)
        self.wait_frames(frames, since=before)

    def press(self, *keys: str) -> None:
        self.xdotool("windowfocus", "--sync", self.window)  # a resize may have taken it
        self.xdotool("key", "--delay", "200", *keys)

    def resize(self, cols: int, rows: int) -> None:
        before = len(frame_times(self.log))
        self.xdotool("windowsize", "--sync", self.window, str(cols * self.cell[0]),
                     str(rows * self.cell[1]))
        time.sleep(4)
        self.wait_frames(3, since=before)

    def shot(self, name: str) -> np.ndarray:
        self.shots += 1
        keep = os.environ.get("CLOTH_TUI_SHOT_DIR")  # to look at them after pytest cleans up
        folder = Path(keep) if keep else self.tmp
        path = folder / f"{self.mode}-{self.shots:02d}-{name}.png"
        subprocess.run(["import", "-display", self.display, "-window", "root",
                        f"PNG24:{path}"], check=True, timeout=30)
        return np.asarray(Image.open(path).convert("RGB"))

    def pair(self, name: str, gap: float = 1.0) -> tuple[np.ndarray, np.ndarray]:
        """Two shots at least `gap` seconds and two new frames apart (a loaded machine
        draws slowly, and a picture that had no new frame cannot have moved)."""
        first = self.shot(name)
        return first, self.later(name + "-later", gap)

    def later(self, name: str, gap: float = 1.0, frames: int = 2) -> np.ndarray:
        since = len(frame_times(self.log))
        time.sleep(gap)
        self.wait_frames(frames, timeout=30, since=since)
        return self.shot(name)

    def until_shown(self, cols, rows, before: np.ndarray, name: str, timeout: float = 12.0
                    ) -> tuple[np.ndarray, np.ndarray]:
        """Screenshots until these cells show something new (unlike `before`) that stays
        put from one shot to the next, e.g. a notice or the drawer once the app has drawn
        it: that pair of shots. On a loaded machine keys take a while to act. At the
        timeout, the last pair, for the checks to find wanting."""
        was = self.cells(before, cols, rows)
        first = self.shot(name)
        deadline = time.monotonic() + timeout
        while True:
            time.sleep(0.3)
            second = self.shot(name)
            a, b = self.cells(first, cols, rows), self.cells(second, cols, rows)
            if (changed(was, b) > 0.2 and changed(a, b) < STILL) or time.monotonic() > deadline:
                return first, second
            first = second

    def until_picture(self, cols, rows, timeout: float = 20.0) -> None:
        """Until these cells hold many colours (a frame for the new size came), or the
        timeout (for the checks to find wanting)."""
        deadline = time.monotonic() + timeout
        while colours(self.cells(self.shot("waiting"), cols, rows)) < 20:
            if time.monotonic() > deadline:
                return
            time.sleep(0.5)

    def cells(self, shot: np.ndarray, cols: tuple[int, int], rows: tuple[int, int]
              ) -> np.ndarray:
        """The pixels of cells [cols) × [rows) (0-based, end excluded)."""
        (x0, y0), (cw, ch) = self.origin, self.cell
        return shot[y0 + rows[0] * ch:y0 + rows[1] * ch, x0 + cols[0] * cw:x0 + cols[1] * cw]


def window_box(shot: np.ndarray) -> tuple[int, int, int, int]:
    """(x0, y0, x1, y1) of the terminal window: what is not the root's black."""
    lit = shot.max(axis=-1) > 0
    ys, xs = np.flatnonzero(lit.any(axis=1)), np.flatnonzero(lit.any(axis=0))
    return xs[0], ys[0], xs[-1] + 1, ys[-1] + 1


def colours(area: np.ndarray) -> int:
    packed = (area[..., 0].astype(np.int64) << 16) | (area[..., 1].astype(np.int64) << 8) \
        | area[..., 2]
    return len(np.unique(packed))


def changed(a: np.ndarray, b: np.ndarray) -> float:
    """Fraction of pixels that differ visibly between two shots of the same cells."""
    return float((np.abs(a.astype(int) - b.astype(int)).max(axis=-1) > 16).mean())


def terminal_background(area: np.ndarray) -> float:
    """Fraction of pixels in the terminal's own background colour: cells the app left."""
    return float((area == TERMINAL_BG).all(axis=-1).mean())


def detail(area: np.ndarray, cell: tuple[int, int]) -> float:
    """Fraction of cells holding more than 3 colours: a half-block cell shows two; a picture
    in pixels shows more in most cells (shading, edges, sixel's dither)."""
    cw, ch = cell
    rich = total = 0
    for y in range(0, area.shape[0] - ch + 1, ch):
        for x in range(0, area.shape[1] - cw + 1, cw):
            total += 1
            rich += colours(area[y:y + ch, x:x + cw]) > 3
    return rich / max(total, 1)


class Findings:
    """What a person would object to, gathered over the whole session so that one run
    reports every item (a broken one early must not hide the others)."""

    def __init__(self) -> None:
        self.problems: list[str] = []

    def check(self, ok, problem: str) -> None:
        if not ok:
            self.problems.append(problem)

    def picture(self, term: Terminal, shots, cols, rows, what: str, least_colours: int = 20
                ) -> None:
        """A picture that moves, with no unpainted pixel, in these cells (a few rows of a
        dithered floor hold only a few of sixel's colours: `least_colours`)."""
        a, b = (term.cells(s, cols, rows) for s in shots)
        bare, n, moved = terminal_background(a), colours(a), changed(a, b)
        self.check(bare < 0.001, f"{what}: the terminal's background shows ({bare:.1%})")
        self.check(n >= least_colours, f"{what}: no picture ({n} colours)")
        self.check(moved > MOVING, f"{what}: the picture does not move ({moved:.2%})")

    def controls(self, term: Terminal, shots, cols, rows, what: str) -> None:
        """Text that stays put, not a moving picture, in these cells."""
        a, b = (term.cells(s, cols, rows) for s in shots)
        bare, n, moved = terminal_background(a), colours(a), changed(a, b)
        self.check(bare < 0.001, f"{what}: the terminal's background shows ({bare:.1%})")
        self.check(moved < STILL, f"{what}: a moving picture covers it ({moved:.2%})")
        self.check(n >= 3, f"{what}: blank, no text")


@pytest.mark.parametrize("mode", ["kitty", "sixel"])
def test_true_pixels_never_hide_the_controls(display, tmp_path, mode):
    if not shutil.which(TERMINALS[mode][0]):
        pytest.skip(f"{TERMINALS[mode][0]} missing")
    term = Terminal(mode, display, tmp_path)
    seen = Findings()
    try:
        term.start()
        cell = term.cell
        preview_rows = ROWS - BELOW_PREVIEW
        panel_at = COLS - DRAWER_COLS

        # Wide, controls beside the preview: a moving picture with detail finer than a cell.
        n0, t0 = len(frame_times(term.log)), time.monotonic()
        shots = term.pair("wide", gap=3)
        fps = (len(frame_times(term.log)) - n0) / (time.monotonic() - t0)
        a = term.cells(shots[0], (0, panel_at - 1), (0, preview_rows))
        print(f"{mode}: {fps:.1f} frames/s shown (UI {ui_ms(term.log):.2f} ms a frame), "
              f"{colours(a)} colours, {detail(a, cell):.0%} cells with detail; {tmp_path}")
        seen.picture(term, shots, (0, panel_at - 1), (0, preview_rows), "wide preview")
        seen.check(detail(a, cell) > 0.3, "wide preview: no detail finer than a cell")
        seen.controls(term, shots, (panel_at + 2, COLS - 1), (1, preview_rows - 1),
                      "the side panel")
        footer_keys = term.cells(shots[0], (0, FOOTER_KEYS_COLS), (ROWS - 1, ROWS))

        # Still (no orbit, paused), then the controls hidden: the preview widens, and sixel's
        # 1000-pixel limit makes its picture shorter. What it no longer reaches is the
        # scene's background, in one colour: not the old picture, not the terminal's.
        term.key("a", "space", settle=3, frames=0)
        term.key("c", settle=4, frames=1)
        still = term.shot("shrunk")
        whole = term.cells(still, (0, COLS), (0, preview_rows))
        seen.check(terminal_background(whole) < 0.001,
                   "controls hidden: the terminal's background shows in the preview")
        if mode == "sixel":
            pw, ph = render_size(COLS, preview_rows, cell, mode)
            right = term.cells(still, (math.ceil(pw / cell[0]), COLS), (0, preview_rows))
            below = term.cells(still, (0, COLS), (math.ceil(ph / cell[1]), preview_rows))
            assert right.size and below.size  # the geometry this step is about
            seen.check(colours(right) == 1, "right of the picture: not one background colour")
            seen.check(colours(below) == 1, "below the shrunk picture: the old one's rows stay")
            seen.check((right[0, 0] == below[0, 0]).all(), "two background colours")

        # Narrower than 120 columns (a resize): every cell painted by the app, the status
        # line and footer free of the picture (the footer's keys look as they did before),
        # and the picture in the preview.
        term.key("a", settle=2, frames=2)  # orbit again (the simulation stays paused)
        cols, rows = NARROW
        preview_rows = rows - BELOW_PREVIEW
        term.resize(cols, rows)
        term.until_picture((0, cols), (0, preview_rows))
        shots = term.pair("narrow")
        grid = term.cells(shots[0], (0, cols), (0, rows))
        seen.check(terminal_background(grid) < 0.001, "after the resize: unpainted cells")
        footer = term.cells(shots[0], (0, FOOTER_KEYS_COLS), (rows - 1, rows))
        same = float((footer == footer_keys).all(axis=-1).mean())
        seen.check(same > 0.99, f"after the resize the footer is not what it was ({same:.0%})")
        seen.picture(term, shots, (0, cols), (0, preview_rows), "narrow preview")

        # A notice over the preview's bottom right: the picture goes on beside it (sixel
        # froze those rows, kitty left them blank) and does not cover it. The notice is at
        # most half the width, one line of text between padding rows, the last of them
        # above the footer: the preview's last row is beside it.
        text = ((cols // 2 + 2, cols // 2 + 20), (rows - 3, rows - 2))  # its line of text
        beside = ((1, cols // 2 - 2), (preview_rows - 1, preview_rows))
        term.press("t")  # physics on one thread: a notice that says so, for 5 s
        shown = term.until_shown(*text, before=shots[1], name="notice")
        later = term.later("notice-later", frames=1)
        seen.controls(term, shown, *text, "the notice")
        seen.picture(term, (shown[0], later), *beside, "beside the notice", least_colours=3)

        # The controls drawer opens over the preview and shows; the picture stays beside it.
        time.sleep(4)  # the notice has gone
        before = term.shot("before-drawer")
        drawer_at = cols - DRAWER_COLS
        panel = ((drawer_at + 2, cols - 2), (1, preview_rows - 1))
        term.press("c")
        shown = term.until_shown(*panel, before=before, name="drawer")
        later = term.later("drawer-later")
        seen.controls(term, shown, *panel, "the drawer")
        seen.controls(term, (shown[0], later), *panel, "the drawer, a second later")
        seen.picture(term, (shown[0], later), (0, drawer_at - 1), (0, preview_rows),
                     "beside the drawer")
    finally:
        term.close()
    assert not seen.problems, f"{mode}: " + "; ".join(seen.problems)
