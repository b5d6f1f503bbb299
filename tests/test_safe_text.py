"""escape_controls: what reaches the terminal from a user's text has no control characters,
and nothing else about the text changes."""

import unicodedata

from hypothesis import given
from hypothesis import strategies as st

from cloth_tui.safe_text import escape_controls

UNSAFE = {"Cc", "Cf", "Zl", "Zp", "Cs"}
# Text rich in what a hostile file name or TOML key may carry: C0/C1 controls, DEL, escape
# sequences, bidi overrides, line separators, lone surrogates, and ordinary letters.
hostile = st.text(st.one_of(
    st.characters(codec=None),
    st.sampled_from(["\x1b", "\n", "\r", "\x07", "\x7f", "\x9b", "\u202e", "\u2028", "\udcff"]),
), max_size=40)


@given(hostile)
def test_no_control_character_survives_and_escaping_is_idempotent(text):
    out = escape_controls(text)
    assert not any(unicodedata.category(c) in UNSAFE for c in out)
    assert "\n" not in out and "\x1b" not in out
    assert escape_controls(out) == out
    out.encode("utf-8")  # printable: no lone surrogate left to fail the terminal's encoder


@given(st.text(st.characters(exclude_categories=tuple(UNSAFE)), max_size=40))
def test_ordinary_text_is_unchanged(text):
    assert escape_controls(text) == text


def test_escapes_are_readable():
    assert escape_controls("a\x1b]0;t\x07\nb\u202e") == "a\\x1b]0;t\\x07\\x0ab\\u202e"
