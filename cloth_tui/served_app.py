"""The app as `cloth-tui serve` runs it for each visitor: `python -m cloth_tui.served_app
SCENE …`, the usual command line with one change to Textual's web driver.

The driver writes its screen updates (from the app's loop) and the chunks of a download
(from its input thread, 64 KiB each) to the same stdout pipe with bare os.write calls. A
write larger than the pipe has room for is split, and the other thread's bytes land in
between: the server then misreads the packet stream, the browser's terminal shows binary
garbage and the download never completes. It happened once the browser fell behind and
the pipe was full. Here every packet is written whole, one at a time."""

from __future__ import annotations

import os
import threading


def serialize_web_driver_writes() -> None:
    from textual.drivers.web_driver import WebDriver

    original_init = WebDriver.__init__

    def __init__(self, *args, **kwargs) -> None:
        original_init(self, *args, **kwargs)
        if not hasattr(self, "_write"):  # a Textual that writes otherwise: leave it be
            return
        fileno, lock = self.fileno, threading.Lock()

        def write_whole(data: bytes) -> None:
            view = memoryview(data)
            with lock:
                while view:
                    view = view[os.write(fileno, view):]

        self._write = write_whole

    WebDriver.__init__ = __init__


if __name__ == "__main__":
    serialize_web_driver_writes()
    from .cli import main

    raise SystemExit(main())
