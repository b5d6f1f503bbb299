"""The app as `cloth-tui serve` runs it for each visitor: `python -m cloth_tui.served_app
SCENE …`, the usual command line with one change to Textual's web driver.

The driver writes its screen updates (from the app's loop) and the chunks of a download
(from its input thread, 64 KiB each) to the same stdout pipe with bare os.write calls. A
write larger than the pipe has room for is split, and the other thread's bytes land in
between: the server then misreads the packet stream, the browser's terminal shows binary
garbage and the download never completes. It happened once the browser fell behind and
the pipe was full. Here every packet is written whole, one at a time.

`served_app --spare SCENE …` is the same app started before its visitor: it imports the app,
runs one frame of the scene and renders one picture (numba compiles the kernels, or loads
them from its cache; the renderer's off-screen check and VTK are done), writes READY on
stderr, then waits for a line "COLUMNS ROWS" on stdin, the visitor's page size, and runs the
app. A visitor then waits for none of that (serve_apps.Spare)."""

from __future__ import annotations

import os
import sys
import threading

SPARE_FLAG = "--spare"
READY = b"cloth-tui: spare app ready\n"
RENDER_WAIT_S = 120.0  # bounds a renderer that never draws; the app then starts anyway


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


def spare_argv(argv: list[str]) -> list[str]:
    """A visitor's app command (serve.app_command's `python -m cloth_tui.served_app …`) as a
    spare's."""
    at = argv.index("cloth_tui.served_app") + 1
    return [*argv[:at], SPARE_FLAG, *argv[at:]]


def warm_up(argv: list[str]) -> None:
    """What the app's start needs done once per process, done before a visitor arrives:
    its modules imported, the scene's kernels compiled or loaded, one picture rendered. A
    bake is replayed, not simulated: its modules only. The compile notice goes to stderr,
    which the server logs."""
    import argparse
    from pathlib import Path

    import cloth_tui.tui.app  # noqa: F401 - Textual and the app's own modules

    parser = argparse.ArgumentParser(add_help=False)
    parser.add_argument("scene")
    parser.add_argument("--set", action="append", default=[], dest="overrides")
    args, _ = parser.parse_known_args(argv)
    if Path(args.scene).suffix.lower() in (".usd", ".usdc", ".usda"):
        return
    from .compile_notice import CompileNotice
    from .render.service import RenderService
    from .scene_files import apply_overrides, load
    from .sim.run.runner import Simulation

    scene = apply_overrides(load(args.scene), args.overrides)
    drawn = threading.Event()
    with CompileNotice(sys.stderr, live=False):
        simulation = Simulation(scene)
        simulation.advance_frame()
        renderer = RenderService(scene=scene, size=(160, 90), on_frame=lambda _: drawn.set(),
                                 on_event=lambda _: drawn.set(), preview_file=False)
        renderer.start()
        renderer.submit(simulation.snapshot())
        drawn.wait(RENDER_WAIT_S)  # a picture, or the event that says none will come
        renderer.stop()


def wait_for_visitor() -> None:
    """Read the visitor's "COLUMNS ROWS" line a byte at a time: whatever follows it on stdin
    is the web driver's."""
    line = bytearray()
    while not line.endswith(b"\n"):
        byte = os.read(0, 1)
        if not byte:  # the server went away before any visitor came
            raise SystemExit(0)
        line += byte
    columns, rows = line.split()
    os.environ["COLUMNS"], os.environ["ROWS"] = columns.decode(), rows.decode()


def run_spare(argv: list[str]) -> None:
    """Warm up, say READY, wait for a visitor; Ctrl+C (the server's process group) or a
    closed stdin before then end it quietly."""
    try:
        warm_up(argv)
        sys.stderr.buffer.write(READY)
        sys.stderr.flush()
        wait_for_visitor()
    except KeyboardInterrupt:
        raise SystemExit(130) from None


if __name__ == "__main__":
    serialize_web_driver_writes()
    if sys.argv[1:2] == [SPARE_FLAG]:
        del sys.argv[1]
        run_spare(sys.argv[1:])
    from .cli import main

    raise SystemExit(main())
