"""What the terminal can show, asked before Textual takes the screen.

Queries (one write, read until the primary device attributes answer or a timeout, so a
terminal that answers nothing delays start-up by the timeout at most and never hangs it):
- kitty graphics `a=q`: a kitty-protocol terminal answers `ESC _ G i=ID;OK ESC \\` before DA1;
- XTVERSION `CSI > 0 q`: the terminal's name and version (`ESC P >| kitty(0.26.5) ESC \\`);
- `CSI 16 t`: the cell size in pixels (`CSI 6 ; height ; width t`);
- DECRQSS of SGR after setting a direct background colour: a terminal that keeps 24-bit
  colour reports `48:2::1:2:3` (or `48;2;1;2;3`) back, one that maps it to a palette does not;
- primary DA `CSI c`: `CSI ? 6x ; … c`, where parameter 4 means sixel.
The cell size falls back to TIOCGWINSZ's ws_xpixel/ws_ypixel. Inside tmux or screen there are
no graphics (they would need pass-through), so nothing is asked and the mode is half-blocks.
"""

from __future__ import annotations

import os
import re
import select
import time
from dataclasses import dataclass, field
from typing import Mapping

from . import kitty

MODES = ("auto", "kitty", "sixel", "blocks")
QUERY_ID = 0x4C43  # the kitty query's image id, not one the preview uses
QUERY_TIMEOUT_S = 0.5
DEFAULT_CELL_PX = (10, 20)  # (w, h) when the terminal tells nothing

_KITTY_OK = re.compile(rb"\x1b_Gi=%d;OK\x1b\\" % QUERY_ID)
_DA1 = re.compile(rb"\x1b\[\?([0-9;]*)c")
_CELL = re.compile(rb"\x1b\[6;(\d+);(\d+)t")
_VERSION = re.compile(rb"\x1bP>\|([^\x1b]*)\x1b\\")
_SGR_REPORT = re.compile(rb"\x1bP1\$r([0-9;:]*)m\x1b\\")
_DIRECT_PROBE = re.compile(rb"48[:;]2[:;]+1[:;]2[:;]3(?![0-9])")


@dataclass(frozen=True)
class Replies:
    """What the terminal answered; `None` where it said nothing."""
    kitty: bool = False
    attributes: tuple[int, ...] | None = None  # primary DA parameters
    cell_px: tuple[int, int] | None = None     # (width, height) from CSI 16 t
    version: str | None = None                 # XTVERSION, e.g. "kitty(0.26.5)"
    direct_color: bool = False                 # kept a 24-bit colour (DECRQSS)

    @property
    def sixel(self) -> bool:
        return self.attributes is not None and 4 in self.attributes[1:]


@dataclass(frozen=True)
class Graphics:
    """The preview's way to draw and what it needs to know about the terminal."""
    mode: str                      # 'kitty' | 'sixel' | 'blocks'
    cell_px: tuple[int, int] = DEFAULT_CELL_PX
    colors: str = "truecolor"      # 'truecolor' | '256' | '16': for half-blocks
    why: str = ""                  # how the mode was chosen, for the status line's tooltip
    replies: Replies = field(default_factory=Replies)

    @property
    def label(self) -> str:
        return self.mode if self.mode != "blocks" else f"blocks {self.colors}"


DIRECT_COLOR_QUERY = "\x1b[48;2;1;2;3m\x1bP$qm\x1b\\\x1b[0m"
QUERIES = (kitty.query(QUERY_ID) + "\x1b[>0q" + "\x1b[16t" + DIRECT_COLOR_QUERY + "\x1b[c"
           ).encode("ascii")


def parse_replies(data: bytes) -> Replies:
    da = _DA1.search(data)
    cell = _CELL.search(data)
    version = _VERSION.search(data)
    return Replies(
        kitty=bool(_KITTY_OK.search(data)),
        attributes=tuple(int(p) for p in da.group(1).split(b";") if p) if da else None,
        cell_px=(int(cell.group(2)), int(cell.group(1))) if cell else None,
        version=version.group(1).decode("utf-8", "replace") if version else None,
        direct_color=any(_DIRECT_PROBE.search(m.group(1)) for m in _SGR_REPORT.finditer(data)))


def ask_terminal(fd_in: int, fd_out: int, timeout: float = QUERY_TIMEOUT_S) -> Replies:
    """Send the queries to `fd_out` and read `fd_in` until the DA1 answer (every terminal
    answers it, and after the others) or `timeout` seconds. The caller puts a tty in
    non-canonical, no-echo mode first (`query_tty` does)."""
    os.write(fd_out, QUERIES)
    data = b""
    deadline = time.monotonic() + timeout
    while not _DA1.search(data):
        left = deadline - time.monotonic()
        if left <= 0 or not select.select([fd_in], [], [], left)[0]:
            break
        chunk = os.read(fd_in, 4096)
        if not chunk:
            break
        data += chunk
    return parse_replies(data)


def query_tty(timeout: float = QUERY_TIMEOUT_S) -> tuple[Replies, tuple[int, int] | None]:
    """Ask the controlling terminal; (replies, cell size from TIOCGWINSZ). Nothing to ask
    (no tty): empty replies."""
    import termios
    try:
        fd = os.open("/dev/tty", os.O_RDWR | os.O_NOCTTY)
    except OSError:
        return Replies(), None
    try:
        cell = winsize_cell_px(fd)
        saved = termios.tcgetattr(fd)
        raw = termios.tcgetattr(fd)
        raw[3] &= ~(termios.ICANON | termios.ECHO)
        raw[6][termios.VMIN], raw[6][termios.VTIME] = 0, 0
        termios.tcsetattr(fd, termios.TCSANOW, raw)
        try:
            return ask_terminal(fd, fd, timeout), cell
        finally:
            termios.tcsetattr(fd, termios.TCSANOW, saved)
    except (OSError, termios.error):
        return Replies(), None
    finally:
        os.close(fd)


def winsize_cell_px(fd: int) -> tuple[int, int] | None:
    """The cell size from the window's pixel size (TIOCGWINSZ), if the terminal sets it."""
    import fcntl
    import struct
    import termios
    try:
        rows, cols, xpx, ypx = struct.unpack(
            "HHHH", fcntl.ioctl(fd, termios.TIOCGWINSZ, b"\0" * 8))
    except OSError:
        return None
    if rows and cols and xpx and ypx:
        return xpx // cols, ypx // rows
    return None


def in_multiplexer(env: Mapping[str, str]) -> bool:
    term = env.get("TERM", "")
    return bool(env.get("TMUX")) or term.startswith(("screen", "tmux"))


_TRUECOLOR_NAMES = ("kitty", "wezterm", "foot", "ghostty", "alacritty", "contour", "konsole",
                    "iterm", "mlterm", "vscode")


def color_depth(env: Mapping[str, str], replies: Replies = Replies(),
                terminfo_colors: int | None = None) -> str:
    """'truecolor', '256' or '16': what the terminal shows, which is often more than it
    announces (TERM=xterm with no COLORTERM makes Rich and Textual assume 16)."""
    if env.get("COLORTERM", "").lower() in ("truecolor", "24bit"):
        return "truecolor"
    term = env.get("TERM", "").lower()
    program = env.get("TERM_PROGRAM", "").lower()
    name = (replies.version or "").lower()
    if replies.kitty or replies.direct_color or "direct" in term or any(
            n in s for n in _TRUECOLOR_NAMES for s in (term, program, name)):
        return "truecolor"
    if "256" in term or (terminfo_colors or 0) >= 256:
        return "256"
    # xterm (XTerm(379) in XTVERSION) and the many terminals that call themselves xterm have
    # had 256 colours for two decades; xterm maps direct colours onto those anyway.
    if term.startswith(("xterm", "rxvt", "gnome", "vte")) or name.startswith("xterm"):
        return "256"
    return "16"


def terminfo_colors(term: str) -> int | None:
    try:
        import curses
        curses.setupterm(term or "dumb", os.open(os.devnull, os.O_WRONLY))
        n = curses.tigetnum("colors")
        return n if n > 0 else None
    except Exception:  # no terminfo entry, no curses: no answer
        return None


def choose(forced: str, env: Mapping[str, str], replies: Replies,
           winsize_cell: tuple[int, int] | None, terminfo: int | None = None) -> Graphics:
    """The mode: `forced` unless 'auto'; else kitty if it answered the query, sixel if DA1
    lists 4, half-blocks otherwise (always inside tmux/screen)."""
    cell = replies.cell_px or winsize_cell or DEFAULT_CELL_PX
    colors = color_depth(env, replies, terminfo)
    if forced != "auto":
        return Graphics(forced, cell, colors, f"--graphics {forced}", replies)
    if in_multiplexer(env):
        return Graphics("blocks", cell, colors, "inside tmux/screen: half-blocks", replies)
    if replies.kitty:
        return Graphics("kitty", cell, colors, "the terminal answered the kitty query", replies)
    if replies.sixel:
        return Graphics("sixel", cell, colors, "the terminal lists sixel (DA1 4)", replies)
    return Graphics("blocks", cell, colors, "no kitty or sixel answer", replies)


def in_browser(env: Mapping[str, str]) -> bool:
    """Served to a web browser (textual-serve runs the app with Textual's web driver): the
    screen is the page's terminal, which shows neither kitty nor sixel pictures, and this
    process's own tty, if any, is the server's terminal, not the one to ask."""
    return "web_driver" in env.get("TEXTUAL_DRIVER", "")


def detect(forced: str = "auto", env: Mapping[str, str] | None = None,
           timeout: float = QUERY_TIMEOUT_S) -> Graphics:
    """Ask the terminal (unless inside tmux/screen) and choose. Forcing a mode still asks,
    for the cell size. In a browser, half-blocks in true colour, whatever was forced."""
    env = os.environ if env is None else env
    if in_browser(env):
        return Graphics("blocks", DEFAULT_CELL_PX, "truecolor", "in a web browser: half-blocks")
    if forced == "auto" and in_multiplexer(env):
        replies, cell = Replies(), None
    else:
        replies, cell = query_tty(timeout)
    return choose(forced, env, replies, cell, terminfo_colors(env.get("TERM", "")))
