"""Command line: argument parsing only. Heavy modules (numba, vtk, textual) load lazily, in
the command that needs them, so `cloth-tui --help` answers at once.

Exit status: 0 success, 2 bad input (one line on stderr), 1 anything unexpected.
"""

from __future__ import annotations

import argparse
import os
import sys
from pathlib import Path

from .usage import UsageError, check_output_path

COMMANDS = ("render", "simulate", "bake", "bench", "accuracy", "lab", "wedge", "serve",
            "scenes")


class _Parser(argparse.ArgumentParser):
    def error(self, message: str) -> None:  # one line, exit 2, no usage dump
        raise UsageError(f"{self.prog}: {message}")


def _add_scene_args(p: argparse.ArgumentParser, optional: bool = False) -> None:
    if optional:
        p.add_argument("scene", nargs="?", default="default",
                       help="scene file (.toml) or built-in scene name (default: default)")
    else:
        p.add_argument("scene", help="scene file (.toml) or built-in scene name")
    p.add_argument("--set", dest="overrides", action="append", default=[], metavar="KEY=VALUE",
                   help="override one scene key, e.g. --set forces.wind=true (repeatable)")


class _VersionAction(argparse.Action):
    """`--version`: the installed package's version, read only when asked."""

    def __init__(self, option_strings, dest, **kwargs):
        super().__init__(option_strings, dest, nargs=0, default=argparse.SUPPRESS,
                         help="print the version and exit")

    def __call__(self, parser, namespace, values, option_string=None):
        from importlib.metadata import PackageNotFoundError, version
        try:
            text = version("cloth-tui")
        except PackageNotFoundError:  # run from a source tree that was never installed
            text = "unknown (not installed)"
        print(f"cloth-tui {text}")
        parser.exit(0)


def _positive_int(text: str) -> int:
    try:
        v = int(text)
    except ValueError:
        raise argparse.ArgumentTypeError(f"{text!r} is not an integer") from None
    if v < 1:
        raise argparse.ArgumentTypeError(f"{text!r} must be ≥ 1")
    return v


def _size_list(text: str) -> list[int]:
    sizes = [_positive_int(t) for t in text.split(",")]
    if any(n < 3 for n in sizes):
        raise argparse.ArgumentTypeError(f"{text!r}: every size must be ≥ 3")
    return sizes


def build_parsers() -> tuple[argparse.ArgumentParser, argparse.ArgumentParser]:
    app = _Parser(prog="cloth-tui",
                  description="A cloth simulator in your terminal. Without a command, opens the "
                              "app on SCENE. Commands: " + ", ".join(COMMANDS) +
                              " (cloth-tui COMMAND --help for each).")
    _add_scene_args(app, optional=True)
    app.add_argument("--version", action=_VersionAction)
    app.add_argument("--captures", default="captures", metavar="DIR",
                     help="folder for screenshots, videos, the preview file and saved scenes "
                          "(default: ./captures)")
    app.add_argument("--graphics", choices=("auto", "kitty", "sixel", "blocks"),
                     default="auto", help="how the preview draws: kitty graphics, sixel or "
                     "half-block cells (default: ask the terminal)")

    cmd = _Parser(prog="cloth-tui")
    sub = cmd.add_subparsers(dest="command", parser_class=_Parser)

    p = sub.add_parser("simulate", help="run a scene headless and print a summary of the state")
    _add_scene_args(p)
    p.add_argument("--frames", type=_positive_int, default=120, help="frames to simulate")
    p.add_argument("--json", action="store_true", help="print one JSON object")
    p.add_argument("--dump", metavar="FILE.npz",
                   help="write final positions, the grid's shape (nz, nx) and, for a square "
                   "grid, its resolution")

    p = sub.add_parser("render", help="render a scene headless to PNG, MP4 or GIF")
    _add_scene_args(p)
    p.add_argument("-o", "--output", required=True, metavar="OUT",
                   help="OUT.png (last frame), OUT.mp4 or OUT.gif")
    p.add_argument("--frames", type=_positive_int, default=None,
                   help="frames to simulate (default: for PNG, 2 s of simulated time, i.e. "
                        "2×frame_rate frames, so the sheet has settled; for video, 90)")
    p.add_argument("--size", default="640x480", metavar="WxH", help="image size in pixels")
    p.add_argument("--fps", type=_positive_int, default=None,
                   help="video frames per second (default: 30; a bake: its own frame rate)")

    p = sub.add_parser("bake", help="simulate and write every frame: USD or OBJ/PLY files")
    _add_scene_args(p)
    p.add_argument("-o", "--output", required=True, metavar="OUT",
                   help="OUT.usd, OUT.usdc, OUT.usda (needs the [usd] extra) or "
                        "OUT_####.obj / OUT_####.ply (one file per frame)")
    p.add_argument("--frames", type=_positive_int, default=120, help="frames to simulate")

    p = sub.add_parser("serve", help="serve the app to web browsers (needs the [serve] extra)")
    _add_scene_args(p, optional=True)
    p.add_argument("--host", default="localhost",
                   help="address to listen on (default: localhost, this machine only; "
                        "0.0.0.0 for every machine that can reach this one)")
    p.add_argument("--port", type=int, default=8000, help="port to listen on (default: 8000)")
    p.add_argument("--captures", default="captures", metavar="DIR",
                   help="folder that keeps every visitor's captures as well "
                        "(default: ./captures)")

    p = sub.add_parser("scenes", help="list the built-in scenes")

    p = sub.add_parser("bench", help="performance benchmarks (numbers, not tests)")
    p.add_argument("--json", action="store_true")
    p.add_argument("--quick", action="store_true", help="fewer sizes and repetitions")
    p.add_argument("--breakdown", metavar="SCENE", help="time each effect of SCENE's step")
    p.add_argument("--contended", action="store_true",
                   help="also time the step with a busy loop taking one core")
    p.add_argument("--sizes", type=_size_list, metavar="N,N,…",
                   help="sheet sizes of the step table (default 26,64,128,256)")
    p.add_argument("--no-render", action="store_true", help="skip render and frame pipeline")
    p.add_argument("--cost-sizes", type=_size_list, metavar="N,N,…",
                   help="sheet sizes of the cost-of-accuracy table (default: --sizes if given, "
                        "else 32,64,128,256; --quick: 32,64)")
    p.add_argument("--no-cost", action="store_true",
                   help="skip the cost-of-accuracy table (the default scene to its tolerance)")

    p = sub.add_parser("accuracy", help="work-precision study of solvers and integrators")
    p.add_argument("--json", action="store_true")
    p.add_argument("--quick", action="store_true", help="a smaller study (under a minute)")
    p.add_argument("--plot", metavar="OUT.png", help="draw the work-precision diagram")
    _add_dask_args(p)

    from .lab.registry import TESTS as LAB_TESTS  # names only: the tests load when run
    p = sub.add_parser("lab", help="the virtual textile lab: run a standard test on the "
                                   "simulator against its computed expectation")
    p.add_argument("test", help="; ".join(f"{k}: {v[2]}" for k, v in LAB_TESTS.items()))
    p.add_argument("--material", metavar="NAME",
                   help="a preset of the measured-fabric table (its areal density, stretch, "
                        "shear and bending)")
    p.add_argument("--resolutions", metavar="N,N,…",
                   help="the resolutions to run (what N is depends on the test; default: "
                        "three, coarse to fine)")
    p.add_argument("--solver", metavar="NAME",
                   help="for the tests of a material (cantilever, peirce, drape): xpbd (the "
                        "default) or hpbd")
    p.add_argument("--json", action="store_true", help="print one JSON object")
    p.add_argument("--plot", metavar="OUT.png",
                   help="draw the error against resolution and against wall time")

    p = sub.add_parser("wedge", help="run SCENE over every combination of --vary values (on "
                                     "Dask) into a labelled contact sheet and a table")
    _add_scene_args(p)
    p.add_argument("--vary", action="append", required=True, metavar="KEY=V1,V2,...",
                   help="a key and its values, e.g. --vary scene.friction=0,0.5,1 (repeatable)")
    p.add_argument("--frames", type=_positive_int, default=None,
                   help="frames per run (default: 2 s of simulated time; with --video, 90)")
    p.add_argument("-o", "--output", required=True, metavar="SHEET",
                   help="SHEET.png (SHEET.mp4 with --video)")
    p.add_argument("--size", default="320x240", metavar="WxH", help="size of each thumbnail")
    p.add_argument("--video", action="store_true", help="each cell a clip: an MP4 grid")
    p.add_argument("--json", action="store_true", help="print one JSON object")
    _add_dask_args(p)
    return app, cmd


def _add_dask_args(p: argparse.ArgumentParser) -> None:
    where = p.add_mutually_exclusive_group()
    where.add_argument("--workers", type=_positive_int, default=None, metavar="N",
                       help="run on a local Dask cluster of N worker processes "
                            "(needs the [wedge] extra)")
    where.add_argument("--scheduler", metavar="ADDRESS",
                       help="run on an existing Dask cluster, e.g. tcp://host:8786")


def cmd_scenes(args) -> int:
    from .resources import builtin_scenes
    for name, path in builtin_scenes().items():
        first = path.read_text(encoding="utf-8").splitlines()[0:1]
        doc = first[0].lstrip("# ").strip() if first and first[0].startswith("#") else ""
        print(f"{name:<20} {doc}")
    return 0


def cmd_simulate(args) -> int:
    import json

    import numpy as np

    from .scene_files import apply_overrides, load

    scene = apply_overrides(load(args.scene), args.overrides)
    if args.dump:
        check_output_path(Path(args.dump), (".npz",))
    from .compile_notice import CompileNotice
    from .interrupt import mesh_grid_progress
    from .sim.runner import Simulation

    with mesh_grid_progress(sys.stderr.isatty()):
        sim = Simulation(scene)
    with CompileNotice(sys.stderr, sys.stderr.isatty()):
        sim.advance_frame()  # compiles (or loads cached) kernels; not counted in wall_s
    sim.reset()
    for _ in range(args.frames):
        sim.advance_frame()
    stats = sim.stats()
    if args.dump:
        from .util import atomic_write
        with atomic_write(Path(args.dump)) as fh:
            m = sim.model
            # `resolution` (particles a side) only where there is one: a reader of older
            # dumps then fails on a rectangle instead of misreading it.
            square = {"resolution": np.int64(m.nx)} if m.nx == m.nz else {}
            np.savez(fh, positions=sim.state.x, shape=np.array(m.shape, np.int64), **square)
    if args.json:
        print(json.dumps(stats.as_dict()))
    else:
        for k, v in stats.as_dict().items():
            print(f"{k:>13}: {v}")
    return 0


def cmd_render(args) -> int:
    from .render.cli import run_render
    return run_render(args)


def cmd_bake(args) -> int:
    from .io.bake_cli import run_bake
    return run_bake(args)


def cmd_bench(args) -> int:
    from .bench.cli import run_bench
    return run_bench(args)


def cmd_accuracy(args) -> int:
    from .bench.accuracy_cli import run_accuracy
    return run_accuracy(args)


def cmd_lab(args) -> int:
    from .lab.cli import run_lab
    return run_lab(args)


def cmd_wedge(args) -> int:
    from .wedge.cli import run_wedge
    return run_wedge(args)


def cmd_serve(args) -> int:
    from .serve import run_serve
    return run_serve(args)


def cmd_app(args) -> int:
    from .scene_files import apply_overrides, load

    if Path(args.scene).suffix.lower() in (".usd", ".usdc", ".usda"):  # a bake: replay it
        from .tui.replay_app import run_replay_app
        return run_replay_app(Path(args.scene), args.overrides, Path(args.captures),
                              graphics=_detect_graphics(args))
    scene = apply_overrides(load(args.scene), args.overrides)
    _build_mesh_grids(scene)
    graphics = _detect_graphics(args)
    from .tui.app import run_app
    return run_app(scene, Path(args.captures), graphics=graphics)


def _build_mesh_grids(scene) -> None:
    """Build the mesh objects' distance grids (cached) before the app takes the terminal:
    their progress shows on it, and a bad mesh file is one line, as for any command."""
    if not any(o.type == "mesh" for o in scene.objects):
        return
    from .interrupt import mesh_grid_progress
    from .sim.colliders import build_colliders
    from .sim.model import build_model

    with mesh_grid_progress(sys.stderr.isatty()):
        build_colliders(scene, build_model(scene.cloth, scene.behavior))


def _detect_graphics(args):
    from .tui.graphics.detect import detect  # before Textual takes the terminal
    return detect(args.graphics)


def _check_thread_limit() -> None:
    from .sim.threads import env_threads
    try:
        env_threads()
    except ValueError as e:
        raise UsageError(str(e)) from None


# OpenBLAS (NumPy's BLAS) runs a long vector's dot product on a second thread, which then
# busy-waits for more work: in the app at 256² the energy statistics' np.dot every 0.2 s kept
# that thread spinning at 40 % of a core, beside the simulation and the renderer on 2 cores.
# Set before NumPy is first imported; a value the user set is kept.
BLAS_THREADS_ENV = "OPENBLAS_NUM_THREADS"


def main(argv: list[str] | None = None) -> int:
    os.environ.setdefault(BLAS_THREADS_ENV, "1")
    argv = list(sys.argv[1:] if argv is None else argv)
    from .safe_text import escape_controls
    from .scene import SceneError

    app_parser, cmd_parser = build_parsers()
    try:
        _check_thread_limit()
        if argv and argv[0] in COMMANDS:
            args = cmd_parser.parse_args(argv)
            handler = globals()[f"cmd_{args.command}"]
        else:
            args = app_parser.parse_args(argv)
            handler = cmd_app
        return handler(args)
    except (UsageError, SceneError) as e:
        message = f"cloth-tui: error: {e}".replace("cloth-tui: error: cloth-tui", "cloth-tui")
        print(escape_controls(message), file=sys.stderr)
        return 2
    except KeyboardInterrupt:
        print("cloth-tui: interrupted", file=sys.stderr)
        return 130
    except BrokenPipeError:
        return 0
    except Exception as e:  # a bug, not bad input: keep the details, show one line
        import tempfile
        import traceback
        fd, log = tempfile.mkstemp(prefix="cloth-tui-crash-", suffix=".log")
        with os.fdopen(fd, "w") as fh:
            traceback.print_exc(file=fh)
        print(escape_controls(f"cloth-tui: internal error: {type(e).__name__}: {e} "
                              f"(traceback in {log})"), file=sys.stderr)
        return 1
