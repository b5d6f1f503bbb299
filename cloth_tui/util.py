"""Small helpers shared by every layer (no heavy imports)."""

from __future__ import annotations

import contextlib
import os
import secrets
from pathlib import Path
from typing import IO, Iterator

NEW_FILE_MODE = 0o666  # what the kernel narrows by the umask, as for any file a program makes
# A new file and only a new file: never an existing one, never through a symbolic link.
EXCLUSIVE_NEW_FILE = (os.O_WRONLY | os.O_CREAT | os.O_EXCL | getattr(os, "O_NOFOLLOW", 0)
                      | getattr(os, "O_CLOEXEC", 0))


@contextlib.contextmanager
def atomic_write(path: str | os.PathLike, mode: str = "wb", encoding: str | None = None, *,
                 durable: bool = True) -> Iterator[IO]:
    """Write to a temp file beside `path`, flush it to disk, then rename over `path`: readers
    never see half a file, and a crash leaves the old file (or none), never a torn one.

    The one way this package writes a file (scenes, PNGs, GIFs, dumps, plots). The temp file
    is created with mode 0666 and the kernel applies the umask, so files get the permissions
    the user's other files get (mkstemp's 0600 would hide them from other users and viewers),
    without changing the process's umask, which other threads share. `durable=False` skips
    the fsync, for a file rewritten several times a second that nobody needs after a crash."""
    path = Path(path)
    folder = path.parent if str(path.parent) else Path(".")
    fd, tmp = _create_temp(folder, path.name)
    try:
        with os.fdopen(fd, mode, encoding=encoding) as fh:
            yield fh
            fh.flush()
            if durable:
                os.fsync(fh.fileno())
        os.replace(tmp, path)
    except BaseException:
        with contextlib.suppress(OSError):
            os.unlink(tmp)
        raise


def _create_temp(folder: Path, name: str) -> tuple[int, Path]:
    for _ in range(100):
        tmp = folder / f".{name}.{secrets.token_hex(4)}.part"
        try:
            return os.open(tmp, EXCLUSIVE_NEW_FILE, NEW_FILE_MODE), tmp
        except FileExistsError:
            continue
    raise FileExistsError(f"no free temporary name for {name} in {folder}")
