"""The hidden temp files a bake saves through (`.NAME.<pid>.<hex>.part.SUFFIX` beside
NAME.SUFFIX, renamed over it when complete), and the removal of those a killed bake left:
a SIGKILL between export and rename leaves one behind, as large as the bake."""

from __future__ import annotations

import contextlib
import os
import re
import secrets
from pathlib import Path

FULL_DISK_BYTES = 64 * 1024  # free space under this after a failed write: the disk is full


def part_path(target: Path) -> Path:
    folder = target.parent if str(target.parent) else Path(".")
    return folder / f".{target.stem}.{os.getpid()}.{secrets.token_hex(4)}.part{target.suffix}"


def remove_stale_parts(target: Path) -> list[Path]:
    """Removes the temp files of `target` whose bake (the pid in the name) has ended; a
    running bake's own, and files of any other name or kind, are left alone."""
    folder = target.parent if str(target.parent) else Path(".")
    pattern = re.compile(rf"\.{re.escape(target.stem)}\.(\d+)\.[0-9a-f]+\.part"
                         rf"{re.escape(target.suffix)}")
    removed = []
    with contextlib.suppress(OSError):
        for entry in os.scandir(folder):
            m = pattern.fullmatch(entry.name)
            if m and entry.is_file(follow_symlinks=False) and not _alive(int(m.group(1))):
                with contextlib.suppress(OSError):
                    os.unlink(entry.path)
                    removed.append(Path(entry.path))
    return removed


def disk_full(folder: Path) -> bool:
    """True when `folder`'s file system has (almost) no space left for this user."""
    try:
        st = os.statvfs(folder if str(folder) else ".")
    except OSError:
        return False
    return st.f_bavail * st.f_frsize < FULL_DISK_BYTES


def _alive(pid: int) -> bool:
    if pid == os.getpid():
        return True
    try:
        os.kill(pid, 0)
    except ProcessLookupError:
        return False
    except (PermissionError, OverflowError):  # another user's process: not ours to judge
        return True
    return True
