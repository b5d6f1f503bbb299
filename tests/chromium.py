"""Headless Chromium, driven over its DevTools protocol on one websocket (aiohttp's client,
which the [serve] extra brings): open a page, press keys, take a screenshot, receive
downloads, and read what the page's websockets receive.

Only what tests/test_serve.py needs; each call waits with a timeout that bounds a failing
test, never one that a passing test measures."""

from __future__ import annotations

import asyncio
import base64
import itertools
import json
import os
import re
import shutil
from pathlib import Path
from typing import Any, Callable

import aiohttp

NAMES = ("chromium", "chromium-browser", "google-chrome", "google-chrome-stable")
FLAGS = ("--headless", "--no-sandbox", "--disable-gpu", "--disable-quic", "--no-first-run",
         "--disable-background-networking", "--disable-component-update", "--disable-sync",
         "--remote-debugging-port=0")
_draining: set[asyncio.Task] = set()  # referenced, so not collected while they run
LISTENING = re.compile(r"DevTools listening on (ws://\S+)")

# Keys as Chromium's Input.dispatchKeyEvent wants them: (key, code, virtual key code, text).
KEYS = {
    "space": (" ", "Space", 32, " "),
    "up": ("ArrowUp", "ArrowUp", 38, ""),
    "i": ("i", "KeyI", 73, "i"),
}


def find_browser() -> str | None:
    for name in NAMES:
        if path := shutil.which(name):
            return path
    return None


class Chromium:
    def __init__(self, process: asyncio.subprocess.Process, http: aiohttp.ClientSession,
                 ws: aiohttp.ClientWebSocketResponse):
        self.process = process
        self.http = http
        self.ws = ws
        self.session_id: str | None = None  # the page's, once opened
        self.events: list[dict] = []
        self._replies: dict[int, asyncio.Future] = {}
        self._ids = itertools.count(1)
        self._new_event = asyncio.Event()
        self._reader = asyncio.create_task(self._read())

    @classmethod
    async def start(cls, executable: str, profile: Path, size=(1600, 1000),
                    timeout: float = 60.0) -> "Chromium":
        process = await asyncio.create_subprocess_exec(
            executable, *FLAGS, f"--user-data-dir={profile}",
            f"--window-size={size[0]},{size[1]}", "about:blank",
            stdin=asyncio.subprocess.DEVNULL, stdout=asyncio.subprocess.DEVNULL,
            stderr=asyncio.subprocess.PIPE)
        try:
            url = await asyncio.wait_for(_devtools_url(process), timeout)
        except BaseException:
            process.kill()
            await process.wait()
            raise
        _draining.add(asyncio.create_task(_drain(process.stderr)))  # a full pipe stalls it
        http = aiohttp.ClientSession()
        ws = await http.ws_connect(url, max_msg_size=0)
        return cls(process, http, ws)

    async def _read(self) -> None:
        async for message in self.ws:
            if message.type != aiohttp.WSMsgType.TEXT:
                continue
            data = json.loads(message.data)
            if "id" in data:
                future = self._replies.pop(data["id"], None)
                if future is not None and not future.done():
                    future.set_result(data)
            else:
                self.events.append(data)
                self._new_event.set()

    async def send(self, method: str, params: dict | None = None, *, page: bool = True,
                   timeout: float = 30.0) -> dict:
        """One DevTools command, to the page's session (or the browser's); its result."""
        n = next(self._ids)
        message: dict[str, Any] = {"id": n, "method": method, "params": params or {}}
        if page and self.session_id is not None:
            message["sessionId"] = self.session_id
        future = asyncio.get_running_loop().create_future()
        self._replies[n] = future
        await self.ws.send_str(json.dumps(message))
        reply = await asyncio.wait_for(future, timeout)
        if "error" in reply:
            raise RuntimeError(f"{method}: {reply['error']}")
        return reply.get("result", {})

    async def wait_for(self, condition: Callable[[], Any], timeout: float, what: str) -> Any:
        """Wait until `condition()` is truthy, rechecked whenever an event arrives."""
        async def poll():
            while not (value := condition()):
                self._new_event.clear()
                try:
                    await asyncio.wait_for(self._new_event.wait(), 0.5)
                except asyncio.TimeoutError:
                    pass
            return value
        try:
            return await asyncio.wait_for(poll(), timeout)
        except asyncio.TimeoutError:
            raise AssertionError(f"timed out after {timeout:g} s waiting for {what}") from None

    async def open(self, url: str, downloads: Path) -> None:
        """A new tab on `url`, its websocket frames reported, downloads saved to
        `downloads` under their guid."""
        await self.send("Browser.setDownloadBehavior",
                        {"behavior": "allowAndName", "downloadPath": str(downloads),
                         "eventsEnabled": True}, page=False)
        target = await self.send("Target.createTarget", {"url": "about:blank"}, page=False)
        attached = await self.send("Target.attachToTarget",
                                   {"targetId": target["targetId"], "flatten": True},
                                   page=False)
        self.session_id = attached["sessionId"]
        # as a tab in front: the page has focus, so its terminal reports focus to the app
        await self.send("Emulation.setFocusEmulationEnabled", {"enabled": True})
        await self.send("Network.enable")
        await self.send("Page.enable")
        await self.send("Page.navigate", {"url": url})

    def received(self) -> bytes:
        """Everything the page's websockets received, binary frames decoded, in order."""
        out = bytearray()
        for e in self.events:
            if e.get("method") == "Network.webSocketFrameReceived":
                frame = e["params"]["response"]
                if frame["opcode"] == 2:
                    out += base64.b64decode(frame["payloadData"])
        return bytes(out)

    def sent(self) -> list[str]:
        """The text frames the page's websockets sent (a terminal's keys: ["stdin", …])."""
        return [e["params"]["response"]["payloadData"] for e in self.events
                if e.get("method") == "Network.webSocketFrameSent"
                and e["params"]["response"]["opcode"] == 1]

    async def focus_terminal(self) -> bool:
        """Focus the page's terminal, as a click on it does, so that keys reach the app;
        whether it then has the focus."""
        return await self.evaluate(
            "(t => { t.focus(); return document.activeElement === t; })"
            "(document.querySelector('.xterm-helper-textarea'))")

    async def focused_element(self) -> str:
        """The tag and classes of the page's focused element, to say where keys went."""
        return await self.evaluate(
            "(e => e ? e.tagName + '.' + e.className : 'none')(document.activeElement)")

    async def press(self, key: str) -> None:
        name, code, vk, text = KEYS[key]
        common = {"key": name, "code": code, "windowsVirtualKeyCode": vk,
                  "nativeVirtualKeyCode": vk}
        await self.send("Input.dispatchKeyEvent",
                        {"type": "keyDown", "text": text, **common} if text else
                        {"type": "rawKeyDown", **common})
        await self.send("Input.dispatchKeyEvent", {"type": "keyUp", **common})

    async def type_from_script(self, text: str) -> None:
        """`text` typed into the page's terminal by a script, not a person: the page gets
        no user activation from it, so a popup it opens in answer is blocked, as one
        opened seconds after a real key press is."""
        await self.evaluate(
            "document.querySelector('.xterm-helper-textarea').dispatchEvent(new InputEvent("
            f"'input', {{data: {json.dumps(text)}, inputType: 'insertText', bubbles: true}}))")

    async def evaluate(self, expression: str) -> Any:
        result = await self.send("Runtime.evaluate",
                                 {"expression": expression, "returnByValue": True})
        return result["result"].get("value")

    async def screenshot(self, path: Path, box: tuple[int, int, int, int] | None = None) -> bytes:
        """A PNG of the page, or of `box` (left, top, right, bottom) in its pixels: a
        small one is taken faster on a busy machine."""
        params: dict[str, Any] = {"format": "png", "optimizeForSpeed": True}
        if box is not None:
            left, top, right, bottom = box
            params["clip"] = {"x": left, "y": top, "width": right - left,
                              "height": bottom - top, "scale": 1}
        shot = await self.send("Page.captureScreenshot", params)
        data = base64.b64decode(shot["data"])
        path.write_bytes(data)
        return data

    def downloads(self, state: str = "completed") -> list[str]:
        """The guids of downloads that reached `state`."""
        return [e["params"]["guid"] for e in self.events
                if e.get("method") == "Browser.downloadProgress"
                and e["params"]["state"] == state]

    def download_names(self) -> dict[str, str]:
        """guid → the file name the server suggested."""
        return {e["params"]["guid"]: e["params"]["suggestedFilename"] for e in self.events
                if e.get("method") == "Browser.downloadWillBegin"}

    async def close(self) -> None:
        try:
            await self.send("Browser.close", page=False, timeout=10)
        except (RuntimeError, asyncio.TimeoutError, ConnectionError):
            pass
        self._reader.cancel()
        await self.http.close()
        try:
            await asyncio.wait_for(self.process.wait(), 10)
        except asyncio.TimeoutError:
            self.process.kill()
            await self.process.wait()


async def _devtools_url(process: asyncio.subprocess.Process) -> str:
    seen = []
    while line := await process.stderr.readline():
        text = line.decode("utf-8", "replace")
        seen.append(text)
        if m := LISTENING.search(text):
            return m.group(1)
    raise RuntimeError("Chromium exited before listening: " + "".join(seen[-20:]))


async def _drain(stream: asyncio.StreamReader) -> None:
    while await stream.read(65536):
        pass


ANSI = re.compile(rb"\x1b\[[0-9;?<>=:]*[ -/]*[@-~]|\x1b[PX^_].*?\x1b\\|\x1b\][^\x07\x1b]*"
                  rb"(?:\x07|\x1b\\)|\x1b[@-Z\\-_]")


def screen_text(data: bytes) -> str:
    """The characters in a terminal stream, its control sequences removed."""
    return ANSI.sub(b"", data).decode("utf-8", "replace")


def os_process_group_gone(pgid: int, within: float = 10.0) -> bool:
    """True once no process is left in the group; waits up to `within` seconds, as an app
    that has closed its pipes (which is what its server waits for) may still be tearing
    down its threads."""
    import time
    deadline = time.monotonic() + within
    while True:
        try:
            os.killpg(pgid, 0)
        except ProcessLookupError:
            return True
        if time.monotonic() > deadline:
            return False
        time.sleep(0.1)
