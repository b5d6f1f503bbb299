"""Running `cloth-tui serve` in a test: a free port, the server in its own process group,
Ctrl+C. Shared by tests/test_serve.py and tests/test_packaging.py (the wheel's serve)."""

import asyncio
import os
import signal
import socket
import subprocess
import sys
from pathlib import Path

SPARE_READY = "the next visitor's app is ready"
START_S = 180.0  # bounds a failing test: an app's first frame took ~40 s on 2 busy cores


_draining: set[asyncio.Task] = set()  # referenced, so not collected while they run


def free_port() -> int:
    with socket.socket() as s:
        s.bind(("127.0.0.1", 0))
        return s.getsockname()[1]


async def start_server(tmp_path: Path, *args: str, env: dict | None = None,
                       keep_output: bool = False, until: str = "Ctrl+C"):
    """`cloth-tui serve` in its own process group (as a shell starts a job); returns the
    process and the lines it printed, up to "Press Ctrl+C" (or the line with `until`: its
    log's SPARE_READY once a visitor's app waits, warmed up). The rest of its output is
    read and dropped, unless `keep_output` (then the caller must read it)."""
    process = await asyncio.create_subprocess_exec(
        sys.executable, "-m", "cloth_tui", "serve", *args,
        stdin=subprocess.DEVNULL, stdout=subprocess.PIPE, stderr=subprocess.STDOUT,
        cwd=tmp_path, env=env, start_new_session=True)
    lines = []
    while not any(until in line for line in lines):
        line = await asyncio.wait_for(process.stdout.readline(), START_S)
        if not line:
            raise AssertionError(f"serve exited {await process.wait()}: {lines}")
        lines.append(line.decode())
    # the visits' log and the apps' stderr, read on: a full pipe would stall the server
    if not keep_output:
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


def group_members(pgid: int) -> list[int]:
    """The processes in process group `pgid` now (zombies too: they are not ended yet)."""
    members = []
    for stat in Path("/proc").glob("[0-9]*/stat"):
        try:
            fields = stat.read_text().rsplit(")", 1)[1].split()
        except OSError:  # exited while listed
            continue
        if int(fields[2]) == pgid:
            members.append(int(stat.parent.name))
    return members


async def visit(port: int, until: str | None, screen_text) -> tuple:
    """A page's websocket to the server on `port`; with `until`, read until the screen
    shows it. The page goes on reading, as a browser does (an unread websocket holds the
    app's output). Returns the http session, the websocket and the reading task (the
    caller closes all three)."""
    import aiohttp
    http = aiohttp.ClientSession()
    ws = await http.ws_connect(f"ws://localhost:{port}/ws?width=160&height=48")
    shown = asyncio.Event()

    async def read():
        screen = bytearray()
        async for message in ws:
            if (until is not None and message.type == aiohttp.WSMsgType.BINARY
                    and not shown.is_set()):
                screen.extend(message.data)
                if until in screen_text(bytes(screen)):
                    shown.set()
    reading = asyncio.create_task(read())
    if until is not None:
        await asyncio.wait([reading, asyncio.create_task(shown.wait())], timeout=START_S,
                           return_when=asyncio.FIRST_COMPLETED)
        assert shown.is_set(), f"the app did not show {until!r}"
    return http, ws, reading
