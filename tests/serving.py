"""Running `cloth-tui serve` in a test: a free port, the server in its own process group,
Ctrl+C. Shared by tests/test_serve.py and tests/test_packaging.py (the wheel's serve)."""

import asyncio
import os
import signal
import socket
import subprocess
import sys
from pathlib import Path

START_S = 180.0  # bounds a failing test: an app's first frame took ~40 s on 2 busy cores


_draining: set[asyncio.Task] = set()  # referenced, so not collected while they run


def free_port() -> int:
    with socket.socket() as s:
        s.bind(("127.0.0.1", 0))
        return s.getsockname()[1]


async def start_server(tmp_path: Path, *args: str, env: dict | None = None):
    """`cloth-tui serve` in its own process group (as a shell starts a job); returns the
    process and the lines it printed, up to "Press Ctrl+C"."""
    process = await asyncio.create_subprocess_exec(
        sys.executable, "-m", "cloth_tui", "serve", *args,
        stdin=subprocess.DEVNULL, stdout=subprocess.PIPE, stderr=subprocess.STDOUT,
        cwd=tmp_path, env=env, start_new_session=True)
    lines = []
    while not any("Ctrl+C" in line for line in lines):
        line = await asyncio.wait_for(process.stdout.readline(), 60)
        if not line:
            raise AssertionError(f"serve exited {await process.wait()}: {lines}")
        lines.append(line.decode())
    # the visits' log and the apps' stderr, read on: a full pipe would stall the server
    _draining.add(asyncio.create_task(_drain(process.stdout)))
    return process, lines


async def _drain(stream) -> None:
    while await stream.read(65536):
        pass


async def interrupt(process) -> int:
    """Ctrl+C as a terminal sends it: SIGINT to the whole process group."""
    os.killpg(process.pid, signal.SIGINT)
    try:
        return await asyncio.wait_for(process.wait(), 30)
    except asyncio.TimeoutError:
        os.killpg(process.pid, signal.SIGKILL)
        raise AssertionError("serve did not stop within 30 s of Ctrl+C") from None
