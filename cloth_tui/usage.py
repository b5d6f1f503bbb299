"""Bad input from the user, and the checks of it that several commands share. Imports
nothing heavy, so any command (and `cloth-tui --help`) can use it at no cost."""

from __future__ import annotations

import contextlib
import os
import secrets
from pathlib import Path


class UsageError(Exception):
    """Bad input from the user: reported as one line, exit status 2."""


def check_output_path(path: Path, suffixes: tuple[str, ...]) -> None:
    """Refuse, before any work is done, an output file that could not be written: a wrong
    type, a folder that is missing or is a file, or one that refuses new files."""
    path = Path(path)
    if path.suffix.lower() not in suffixes:
        raise UsageError(f"{path}: unsupported file type; use {', '.join(suffixes)}")
    folder = path.parent if str(path.parent) else Path(".")
    try:
        is_dir, folder_exists = path.is_dir(), folder.exists()
    except OSError as e:  # a name longer than the file system allows
        raise UsageError(f"{path}: {e.strerror or type(e).__name__}") from None
    if is_dir:  # the final rename would fail only after all the work
        raise UsageError(f"{path}: is a folder; name a file to write")
    if folder_exists and not folder.is_dir():
        raise UsageError(f"{path}: {folder} is not a folder")
    if not folder.is_dir():
        raise UsageError(f"{path}: folder {folder} does not exist")
    # Try it rather than ask os.access: root "may" write anywhere by permissions, yet
    # /sys, read-only mounts and full disks still refuse.
    probe = folder / f".{path.name}.{secrets.token_hex(4)}.probe"
    try:
        os.close(os.open(probe, os.O_WRONLY | os.O_CREAT | os.O_EXCL, 0o600))
    except OSError as e:
        raise UsageError(f"{path}: cannot write in folder {folder}: "
                         f"{e.strerror or type(e).__name__}") from None
    with contextlib.suppress(OSError):
        os.unlink(probe)
