"""Detection: the replies of fake terminals through a pty, the timeout, tmux and colours."""

import os
import pty
import threading
import time

import pytest

from cloth_tui.tui.graphics import detect
from cloth_tui.tui.graphics.detect import Replies, ask_terminal, choose, color_depth

KITTY_REPLIES = (b"\x1b_Gi=%d;OK\x1b\\" % detect.QUERY_ID + b"\x1bP>|kitty(0.26.5)\x1b\\"
                 + b"\x1b[6;20;9t" + b"\x1bP1$r0;48:2::1:2:3m\x1b\\" + b"\x1b[?62;c")
XTERM_REPLIES = (b"\x1bP>|XTerm(379)\x1b\\" + b"\x1bP1$r0;48;2;1;2;3m\x1b\\"
                 + b"\x1b[?63;1;2;4;6;9;15;16;22;28c")
PLAIN_REPLIES = b"\x1bP1$r0;48;5;16m\x1b\\\x1b[?1;2c"  # a VT100-like answer, palette colour


def fake_terminal(replies: bytes, delay: float = 0.0):
    """A pty whose 'terminal' end answers the queries once it has read them all."""
    master, slave = pty.openpty()
    import tty
    tty.setraw(slave)
    seen = bytearray()

    def answer():
        while not seen.endswith(b"\x1b[c"):
            seen.extend(os.read(master, 4096))
        time.sleep(delay)
        if replies:
            os.write(master, replies)

    t = threading.Thread(target=answer, daemon=True)
    t.start()
    return master, slave, seen


@pytest.mark.parametrize("replies, mode, colors, cell", [
    (KITTY_REPLIES, "kitty", "truecolor", (9, 20)),
    (XTERM_REPLIES, "sixel", "truecolor", (7, 14)),
    (PLAIN_REPLIES, "blocks", "256", (7, 14)),
])
def test_replies_through_a_pty_choose_the_mode(replies, mode, colors, cell):
    master, slave, seen = fake_terminal(replies)
    try:
        got = ask_terminal(slave, slave, timeout=2.0)
    finally:
        os.close(master), os.close(slave)
    assert bytes(seen) == detect.QUERIES  # every query written, DA1 last
    g = choose("auto", {"TERM": "xterm"}, got, winsize_cell=(7, 14))
    assert (g.mode, g.colors, g.cell_px) == (mode, colors, cell)


def test_a_silent_terminal_costs_the_timeout_and_no_more():
    master, slave, _ = fake_terminal(b"")
    try:
        t0 = time.monotonic()
        got = ask_terminal(slave, slave, timeout=0.3)
        waited = time.monotonic() - t0
    finally:
        os.close(master), os.close(slave)
    assert got == Replies()
    assert 0.25 < waited < 2.0  # behaviour, not speed: it returned, after the timeout
    assert choose("auto", {"TERM": "xterm"}, got, None).mode == "blocks"


def test_tmux_gets_half_blocks_without_asking(monkeypatch):
    def no_query(timeout):
        raise AssertionError("asked the terminal inside tmux")

    monkeypatch.setattr(detect, "query_tty", no_query)
    env = {"TMUX": "/tmp/tmux-0/default,1,0", "TERM": "tmux-256color"}
    g = detect.detect("auto", env)
    assert g.mode == "blocks" and g.colors == "256" and "tmux" in g.why
    # even a kitty reply does not lift it: the picture would not pass through tmux
    assert choose("auto", env, Replies(kitty=True), None).mode == "blocks"


def test_forced_mode_wins_and_still_asks_for_the_cell_size(monkeypatch):
    monkeypatch.setattr(detect, "query_tty", lambda timeout: (Replies(cell_px=(8, 16)), None))
    g = detect.detect("sixel", {"TERM": "xterm"})
    assert g.mode == "sixel" and g.cell_px == (8, 16)


@pytest.mark.parametrize("forced", ["auto", "kitty", "sixel"])
def test_a_browser_gets_half_blocks_in_truecolor_without_asking(monkeypatch, forced):
    def no_query(timeout):
        raise AssertionError("asked the tty: under textual-serve it is the server's terminal")

    monkeypatch.setattr(detect, "query_tty", no_query)
    env = {"TEXTUAL_DRIVER": "textual.drivers.web_driver:WebDriver", "TERM": "xterm-kitty"}
    g = detect.detect(forced, env)
    assert (g.mode, g.colors, g.label) == ("blocks", "truecolor", "blocks truecolor")
    assert "browser" in g.why


@pytest.mark.parametrize("env, replies, depth", [
    ({"TERM": "xterm"}, Replies(), "256"),  # TERM=xterm, no COLORTERM: not 16
    ({"TERM": "xterm", "COLORTERM": "truecolor"}, Replies(), "truecolor"),
    ({"TERM": "xterm"}, Replies(direct_color=True), "truecolor"),
    ({"TERM": "xterm-kitty"}, Replies(), "truecolor"),
    ({"TERM": "screen-256color"}, Replies(), "256"),
    ({"TERM": "linux"}, Replies(), "16"),
    ({"TERM": "vt100"}, Replies(), "16"),
])
def test_color_depth(env, replies, depth):
    assert color_depth(env, replies, terminfo_colors=None) == depth


def test_sgr_report_with_a_palette_colour_is_not_truecolor():
    assert not detect.parse_replies(PLAIN_REPLIES).direct_color
    assert detect.parse_replies(XTERM_REPLIES).direct_color
    assert detect.parse_replies(KITTY_REPLIES).sixel is False
    assert detect.parse_replies(XTERM_REPLIES).sixel
