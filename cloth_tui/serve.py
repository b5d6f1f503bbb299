"""`cloth-tui serve`: the app in a web browser, through Textual's own web server
(textual-serve, the optional `[serve]` extra).

The server runs no simulation itself: each browser that opens the page gets its own app process
(`python -m cloth_tui.served_app SCENE …`), whose screen and keys travel over a websocket. In there
the preview draws in half-block cells (graphics/detect.py sees the web driver) and every capture is
also handed to the browser as a download (capture_actions.py).

A visitor's app would spend seconds starting (imports, numba's kernels, the renderer's start)
before its first picture, and a minute on a cold numba cache. So the server keeps one spare app
that has done all that (serve_apps.Spare), from its start: the first spare's compile notice is
the server's own start-up report. The next visitor takes it; a new one is started a little later.
"""

from __future__ import annotations

import ipaddress
import os
import shlex
import socket
import sys
import time
from pathlib import Path
from typing import Any

from .usage import UsageError

MISSING_EXTRA = ("serve needs the [serve] extra (textual-serve): "
                 "pip install 'cloth-tui[serve]'")
BAKE_SUFFIXES = (".usd", ".usdc", ".usda")
# s after a visitor took the spare before the next one starts: its warm-up would take a core
# from the visitor's app while that starts and draws its first pictures
NEXT_SPARE_AFTER_S = 30.0


def is_local(host: str) -> bool:
    """True when only this machine can connect to `host` (a loopback name or address)."""
    if host.lower() in ("localhost", "localhost.localdomain", "ip6-localhost"):
        return True
    try:
        return ipaddress.ip_address(host.strip("[]")).is_loopback
    except ValueError:  # a host name: it may resolve to an outside address
        return False


def app_command(scene: str, overrides: list[str], captures_dir: Path) -> str:
    """The command line of each visitor's app: this Python, this package (served_app:
    the app with Textual's web driver made safe for downloads)."""
    argv = [sys.executable, "-m", "cloth_tui.served_app", scene]
    for override in overrides:
        argv += ["--set", override]
    argv += ["--captures", str(captures_dir)]
    return shlex.join(argv)


def check_scene(scene: str, overrides: list[str]) -> str:
    """Refuse a scene (or bake) the app would refuse, once here rather than on every visitor's
    page; return the argument to hand the app, a file as an absolute path."""
    if Path(scene).suffix.lower() in BAKE_SUFFIXES:
        from .io.usd_read import UsdBake
        from .render.replay import bake_scene
        bake_scene(UsdBake(Path(scene)), overrides)
        return str(Path(scene).resolve())
    from .scene_files import apply_overrides, load
    apply_overrides(load(scene), overrides)
    return str(Path(scene).resolve()) if Path(scene).is_file() else scene


def check_captures(captures_dir: Path) -> Path:
    try:
        captures_dir.mkdir(parents=True, exist_ok=True)
        if not os.access(captures_dir, os.W_OK):
            raise PermissionError(13, "not writable")
    except OSError as e:
        raise UsageError(f"cannot use captures folder {captures_dir}: "
                         f"{e.strerror or e}") from None
    return captures_dir.resolve()


def start_lines(host: str, port: int, captures_dir: Path) -> list[str]:
    """What the server says when it is listening."""
    url = f"http://{host if ':' not in host else f'[{host}]'}:{port}"
    if is_local(host):
        reach = (f"Listening on {host} only: other machines cannot connect "
                 f"(--host 0.0.0.0 lets them).")
    else:
        reach = (f"Listening on {host}: other machines can connect, and anyone who reaches "
                 f"port {port} can run the app.")
    return [f"cloth-tui serve: open {url} in a web browser.", reach,
            f"Each browser tab runs its own app; captures are downloaded by the browser and "
            f"kept in {captures_dir}.",
            "Press Ctrl+C to stop the server and every app."]


# s between the server's pings to a page; a page that has not answered within half of it is
# taken for gone and its app ended. A page behind on pictures answers a ping only when it
# reaches it in the stream (textual-serve's 15 s closed busy pages' apps after 7.5 s).
HEARTBEAT_S = 60.0


def make_server(command: str, host: str, port: int, captures_dir: Path) -> Any:
    import asyncio
    import logging
    import signal

    from aiohttp import web
    from aiohttp.web_runner import GracefulExit
    from textual_serve.server import Server, to_int

    from .serve_apps import Spare, VisitorApp, with_download_links

    visits: dict[asyncio.Task, VisitorApp] = {}  # one per open page: its handler, its app

    class ClothServer(Server):
        exiting = False
        spare: asyncio.Task | None = None  # starting the next visitor's app (a Spare)
        next_spare: asyncio.TimerHandle | None = None
        # spares nobody could take (a visitor came while one was still being spawned),
        # being ended: the shutdown waits for them too, or the loop closes under them
        passed_over: set[asyncio.Task] = set()

        def serve(self, debug: bool = False) -> None:
            """textual-serve's own `serve`, but the start lines are printed once the port is
            bound (a taken port fails before any of them), and a fresh event loop."""
            self.debug = debug
            self.initialize_logging()
            # one line per visitor (handle_websocket) says more than aiohttp's request log
            logging.getLogger("aiohttp.access").setLevel(logging.WARNING)
            loop = asyncio.new_event_loop()
            for sig in (signal.SIGINT, signal.SIGTERM):
                loop.add_signal_handler(sig, self.request_exit)
            web.run_app(self._make_app(), host=self.host, port=self.port,
                        handle_signals=False, loop=loop, print=self._listening)

        def request_exit(self) -> None:
            """The first Ctrl+C or SIGTERM starts the shutdown; more, while the apps are
            ending, change nothing (the shutdown is already under way)."""
            if not self.exiting:
                self.exiting = True
                raise GracefulExit()

        def _listening(self, _aiohttp_banner: str) -> None:
            for line in start_lines(host, port, captures_dir):
                print(line, flush=True)  # flushed: a pipe (a test, a log) sees it at once
            self.start_spare()

        def start_spare(self) -> None:
            self.next_spare = None
            if not self.exiting:
                self.spare = asyncio.get_running_loop().create_task(
                    Spare.start(self.command, self.debug, _log))

        def take_spare(self) -> Spare | None:
            """The spare app for a visitor (None if it is not even a process yet); the
            next one is started NEXT_SPARE_AFTER_S later."""
            spare, self.spare = self.spare, None
            if (spare is None or not spare.done() or spare.cancelled()
                    or spare.exception() is not None):
                if spare is not None:
                    ending = asyncio.get_running_loop().create_task(_end_spare_task(spare))
                    self.passed_over.add(ending)
                    ending.add_done_callback(self.passed_over.discard)
                return None
            if self.next_spare is None and not self.exiting:
                self.next_spare = asyncio.get_running_loop().call_later(
                    NEXT_SPARE_AFTER_S, self.start_spare)
            return spare.result()

        async def on_startup(self, app) -> None:
            """Nothing: textual-serve prints its banner here, before the port is bound."""

        async def handle_websocket(self, request):
            """One visitor's app, from the page's connection until the app process has
            exited (not just closed its output): the count of running apps is true, and a
            page closed while its app starts up still ends that app."""
            websocket = web.WebSocketResponse(heartbeat=HEARTBEAT_S)
            width = to_int(request.query.get("width", "80"), 80)
            height = to_int(request.query.get("height", "24"), 24)
            await websocket.prepare(request)
            app = VisitorApp(self.command, websocket, self.download_manager, self.debug,
                             self.take_spare)
            task = asyncio.current_task()
            visits[task] = app
            _log(f"{request.remote} opened the app ({len(visits)} running)")
            try:
                await app.start(width, height)
                await self._process_messages(websocket, app)
            except asyncio.CancelledError:  # the server's shutdown
                pass
            except Exception as error:  # noqa: BLE001 - a broken page ends its own app only
                _log(f"{request.remote}: {type(error).__name__}: {error}")
            finally:
                await asyncio.shield(app.stop())
                await websocket.close()
                del visits[task]
                _log(f"{request.remote} left: its app stopped ({len(visits)} running)")
            return websocket

        async def on_shutdown(self, app) -> None:
            """Ctrl+C or SIGTERM: end every visit now and wait until each one's app has
            exited, so that the server exits after its apps and none is left running."""
            self.exiting = True  # no new spare from now on
            if self.next_spare is not None:
                self.next_spare.cancel()
            visitors = list(visits.values())
            for task, visitor in list(visits.items()):
                if not visitor.stopping:  # in its start or its messages: to its `finally`
                    task.cancel()
            ending = [visitor.stop() for visitor in visitors]
            if self.spare is not None:
                ending.append(asyncio.ensure_future(_end_spare_task(self.spare)))
            ending += list(self.passed_over)
            if ending:
                await asyncio.wait(ending)

        async def handle_index(self, request):
            """The page connects its websocket back to the address the browser used: with
            --host 0.0.0.0 the configured one is no address a browser can reach. Its
            downloads start by a link (serve_apps.DOWNLOAD_BY_LINK)."""
            self.public_url = f"{request.scheme}://{request.host}"
            response = await super().handle_index(request)
            response.text = with_download_links(response.text)
            return response

    return ClothServer(command, host=host, port=port, title="cloth-tui")


def check_host(host: str) -> str:
    """Refuse a --host no socket can listen on, in one line (a 300-character name made
    the IDNA codec raise deep inside asyncio)."""
    if not host.strip():
        raise UsageError("--host is empty: give 0.0.0.0 to listen on every interface, "
                         "or localhost for this machine only")
    try:
        ipaddress.ip_address(host.strip("[]"))
        return host
    except ValueError:
        pass
    try:
        encoded = host.encode("idna")
    except UnicodeError:
        raise UsageError(f"--host {_short(host)}: not a host name or address") from None
    if len(encoded) > 253:
        raise UsageError(f"--host {_short(host)}: a host name has at most 253 characters")
    return host


def _short(text: str) -> str:
    return repr(text if len(text) <= 40 else text[:37] + "...")


def run_serve(args) -> int:
    try:
        import textual_serve.server  # noqa: F401
    except ImportError:
        raise UsageError(MISSING_EXTRA) from None
    if not 1 <= args.port <= 65535:
        raise UsageError(f"--port {args.port}: must be 1…65535")
    scene = check_scene(args.scene, args.overrides)
    captures_dir = check_captures(Path(args.captures))
    check_host(args.host)
    command = app_command(scene, args.overrides, captures_dir)
    server = make_server(command, args.host, args.port, captures_dir)
    try:
        server.serve()
    except OSError as e:  # the port is taken, the host unknown or not this machine's
        raise UsageError(f"cannot listen on {args.host}:{args.port}: "
                         f"{_reason(e)}") from None
    except UnicodeError:  # a name check_host let through that the IDNA codec refuses
        raise UsageError(f"--host {_short(args.host)}: not a host name or address") from None
    return 0


async def _end_spare_task(starting) -> None:
    """The spare `starting` spawns, ended once it is a process (none: nothing to end)."""
    try:
        spare = await starting
    except Exception:  # noqa: BLE001 - no process was started: nothing to end
        return
    await spare.end()


def _log(text: str) -> None:
    print(f"{time.strftime('%H:%M:%S')} {text}", flush=True)


def _reason(error: OSError) -> str:
    """'Address already in use', not asyncio's sentence that repeats the address."""
    if isinstance(error, socket.gaierror) or not error.errno:
        return error.strerror or str(error)
    return os.strerror(error.errno)
