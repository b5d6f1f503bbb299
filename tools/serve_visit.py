"""Visit a running `cloth-tui serve` as a browser page does, over its websocket, and wait
until the visitor's app draws its status line (which names the preview's mode, half-blocks
in a browser). CI runs it against the installed wheel, where no browser is needed for this
much; tests/test_serve.py has the browser. Needs aiohttp (the [serve] extra brings it).

    python tools/serve_visit.py PORT [--host HOST] [--timeout S]

Exit 0 when the status line is seen; 1, with the last text received, when it is not.
"""

from __future__ import annotations

import argparse
import asyncio
import sys

import aiohttp

SEEN = b"blocks truecolor"  # the status line's mode, once the app runs in the page


async def visit(host: str, port: int, timeout: float) -> tuple[bool, bytes]:
    """Connect (again, until the server listens) and read until the status line is seen,
    the app ends, or `timeout` seconds pass."""
    received = bytearray()

    async def read(http: aiohttp.ClientSession) -> bool:
        url = f"ws://{host}:{port}/ws?width=160&height=48"
        while True:
            try:
                ws = await http.ws_connect(url)
                break
            except aiohttp.ClientConnectorError:  # not listening yet
                await asyncio.sleep(0.5)
        async with ws:
            async for message in ws:
                if message.type == aiohttp.WSMsgType.BINARY:
                    received.extend(message.data)
                    if SEEN in received:
                        return True
        return False  # the app ended before drawing it

    async with aiohttp.ClientSession() as http:
        try:
            return await asyncio.wait_for(read(http), timeout), bytes(received)
        except asyncio.TimeoutError:
            return False, bytes(received)


def main() -> int:
    p = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    p.add_argument("port", type=int)
    p.add_argument("--host", default="localhost")
    p.add_argument("--timeout", type=float, default=180.0)
    args = p.parse_args()
    ok, received = asyncio.run(visit(args.host, args.port, args.timeout))
    if ok:
        print(f"serve_visit: the app's status line arrived ({len(received)} bytes)")
        return 0
    tail = received[-600:].decode("utf-8", "replace")
    print(f"serve_visit: no status line in {len(received)} bytes; last: {tail!r}",
          file=sys.stderr)
    return 1


if __name__ == "__main__":
    sys.exit(main())
