"""Text that is safe to show the user: every error message and notice passes through here.

Scene keys, values and file names come from the user's files and arguments. Shown raw, a
control character in them could drive the terminal (escape sequences retitle it or recolour
what follows) or break the one-line contract of error messages (a newline). So control
characters are shown as Python escapes (`\\x1b`, `\\n`, `\\u202e`) instead.
"""

from __future__ import annotations

import unicodedata

# Cc: C0/C1 controls and DEL; Cf: invisible format characters (bidi overrides reorder what
# follows them); Zl/Zp: line and paragraph separators; Cs: lone surrogates, which is how
# Python decodes the bytes of a file name that is not UTF-8 and which cannot be printed.
_UNSAFE_CATEGORIES = frozenset({"Cc", "Cf", "Zl", "Zp", "Cs"})


def _escape(ch: str) -> str:
    code = ord(ch)
    if code < 0x100:
        return f"\\x{code:02x}"
    if code < 0x10000:
        return f"\\u{code:04x}"
    return f"\\U{code:08x}"


def escape_controls(text: object) -> str:
    """`text` as a string with control characters escaped. Idempotent: an escaped text has
    no control characters left, so escaping it again changes nothing."""
    s = str(text)
    if s.isprintable():  # the common case: nothing to do (spaces count as printable)
        return s
    return "".join(_escape(c) if unicodedata.category(c) in _UNSAFE_CATEGORIES else c
                   for c in s)
