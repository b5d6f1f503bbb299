"""One visitor's app process under `cloth-tui serve` (textual-serve's AppService), ended
for certain: asked to quit, then SIGTERM, then SIGKILL, each after a grace period, and
waited for until the process has exited. And the spare app (`Spare`): the next visitor's
app, started and warmed up before that visitor arrives.

textual-serve's own service waits only for the app to close its output, so the server
could exit (or count "0 running") while an app was still tearing down, and an app whose
visitor left while it was starting up could be left running for good."""

from __future__ import annotations

import asyncio
import contextlib
import shlex
import signal
import time
from types import SimpleNamespace
from typing import Callable

from textual_serve.app_service import AppService

from .served_app import READY, spare_argv

QUIT_S = 10.0  # a running app told to quit: its last frame, its threads, its recording
TERM_S = 5.0  # after SIGTERM (the app's own handler ends it and has a watchdog)
KILL_S = 5.0  # after SIGKILL: the kernel's part only
OUTPUT_S = 5.0  # the app's output read to its end once the process is gone


# textual-serve's page opens each download with window.open when the app's message arrives;
# a popup blocker refuses that unless a key was pressed in the last few seconds, and under
# load the message came later (the screenshot was saved, no download began). A link's
# click starts a download without a popup.
DOWNLOAD_BY_LINK = """<script>
(() => {
  const open = window.open.bind(window);
  window.open = (url, target, ...rest) => {
    if (new URL(url, location.href).pathname.startsWith("/download/")) {
      const link = document.createElement("a");
      link.href = url;
      link.download = "";
      document.body.appendChild(link);
      link.click();
      link.remove();
      return null;
    }
    return open(url, target, ...rest);
  };
})();
</script>
"""


def with_download_links(page: str) -> str:
    """The app's page, its downloads started by a link rather than a popup."""
    return page.replace("</head>", DOWNLOAD_BY_LINK + "</head>", 1)


# Screen updates a second an app sends its page (textual-serve asks 60). A page's terminal
# parses every update of the half-block picture; on a busy machine it fell behind a stream of
# 60, and then its own frames (keys, the heartbeat's replies) no longer reached the server.
PAGE_UPDATES_PER_S = 30


def app_environment(debug: bool, width: int = 80, height: int = 24) -> dict[str, str]:
    """The environment textual-serve gives an app process (its web driver, its colours),
    also for a spare, started before its page's size is known."""
    env = AppService._build_environment(SimpleNamespace(debug=debug), width, height)
    env["TEXTUAL_FPS"] = str(PAGE_UPDATES_PER_S)
    return env


class Spare:
    """An app process started before its visitor (served_app --spare): it imports, compiles
    or loads the kernels and renders once, then waits for a page's size. `ready` (a task)
    says whether it got that far; until then its stderr is read here, the compile notice
    handed to `log`. Owned by the server until a VisitorApp takes it, then by that."""

    def __init__(self, process: asyncio.subprocess.Process, log: Callable[[str], None]):
        self.process = process
        self.ready = asyncio.get_running_loop().create_task(self._warmed_up(log))

    @classmethod
    async def start(cls, command: str, debug: bool, log: Callable[[str], None]) -> "Spare":
        process = await asyncio.create_subprocess_exec(
            *spare_argv(shlex.split(command)), stdin=asyncio.subprocess.PIPE,
            stdout=asyncio.subprocess.PIPE, stderr=asyncio.subprocess.PIPE,
            env=app_environment(debug))
        return cls(process, log)

    async def _warmed_up(self, log: Callable[[str], None]) -> bool:
        started = time.monotonic()
        while line := await self.process.stderr.readline():
            if line == READY:
                log(f"the next visitor's app is ready (warmed up in "
                    f"{time.monotonic() - started:.0f} s)")
                return True
            if text := line.decode("utf-8", "replace").strip():
                log(text)
        return False  # it ended (or its stderr closed) before it was ready

    async def end(self) -> None:
        """The server's spare, never taken: ended like a visitor's app still starting up."""
        await _end_process(self.process, started=False)
        self.ready.cancel()


class VisitorApp(AppService):
    def __init__(self, command: str, websocket, download_manager, debug: bool,
                 take_spare: Callable[[], Spare | None] = lambda: None) -> None:
        self._websocket = websocket
        self._take_spare = take_spare
        super().__init__(command, write_bytes=self._send_bytes, write_str=self._send_str,
                         close=websocket.close, download_manager=download_manager,
                         debug=debug)
        self._stopping: asyncio.Task | None = None
        self.started = False  # the app has drawn: it reads its input and can be told to quit

    @property
    def stopping(self) -> bool:
        return self._stopping is not None

    async def _open_app_process(self, width: int = 80, height: int = 24):
        """The server's spare app, told this page's size, if there is one that warmed up;
        else a new one. The app itself as the child, not a shell around it: the signals
        below reach it (sh -c would take them and leave the app running)."""
        spare = self._take_spare()
        if spare is not None:
            self._process = spare.process  # ended by `stop` even while it warms up
            self._stdin = spare.process.stdin
            if await spare.ready:
                self._stdin.write(f"{width} {height}\n".encode())
                return spare.process
        environment = app_environment(self.debug, width, height)
        self._process = process = await asyncio.create_subprocess_exec(
            *shlex.split(self.command), stdin=asyncio.subprocess.PIPE,
            stdout=asyncio.subprocess.PIPE, stderr=asyncio.subprocess.PIPE, env=environment)
        self._stdin = process.stdin
        return process

    async def on_data(self, payload: bytes) -> None:
        self.started = True
        await self._send_bytes(payload)

    async def _send_bytes(self, data: bytes) -> None:
        """To the page, unless it has gone: the app's output is still read to its end (an
        app blocked on a full pipe would never see the request to quit)."""
        if not self._websocket.closed:
            with contextlib.suppress(ConnectionError):
                await self._websocket.send_bytes(data)

    async def _send_str(self, data: str) -> None:
        if not self._websocket.closed:
            with contextlib.suppress(ConnectionError):
                await self._websocket.send_str(data)

    def stop(self) -> asyncio.Task:
        """Ends the app (once, however often called); the task finishes when the process
        has exited and its output is read."""
        if self._stopping is None:
            self._stopping = asyncio.get_running_loop().create_task(self._end())
        return self._stopping

    async def _end(self) -> None:
        process = self._process
        if process is None:
            return
        await self._download_manager.cancel_app_downloads(app_service_id=self.app_service_id)
        if process.returncode is None and self.started:
            await self.send_meta({"type": "quit"})
        await _end_process(process, self.started)
        if self._task is not None:
            done, _ = await asyncio.wait([self._task], timeout=OUTPUT_S)
            if not done:  # a child of the app holds its output open
                self._task.cancel()
                await asyncio.wait([self._task])
            self._task = None


async def _end_process(process: asyncio.subprocess.Process, started: bool) -> None:
    """After a request to quit (an app that has `started` was sent one), SIGTERM, then
    SIGKILL, each after its grace period, until the process has exited. An app still
    starting up reads no input yet, so it is not waited for before SIGTERM."""
    if started:
        await _wait(process, QUIT_S)
    for sig, grace in ((signal.SIGTERM, TERM_S), (signal.SIGKILL, KILL_S)):
        if process.returncode is not None:
            break
        with contextlib.suppress(ProcessLookupError):
            process.send_signal(sig)
        await _wait(process, grace)


async def _wait(process: asyncio.subprocess.Process, seconds: float) -> None:
    with contextlib.suppress(asyncio.TimeoutError):
        await asyncio.wait_for(process.wait(), seconds)
