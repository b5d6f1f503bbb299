"""The command line's arguments: the app's parser and the commands' parsers. Imported by
`cli.main` inside its guard, so nothing here runs before Ctrl+C is handled; imports nothing
heavy, so `cloth-tui --help` answers at once."""

from __future__ import annotations

import argparse

from .usage import UsageError

COMMANDS = ("render", "simulate", "bake", "bench", "accuracy", "lab", "wedge", "serve",
            "scenes", "materials")


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
    """The bench's sheet sizes, refused before any work beyond what a scene's sheet can be
    (cloth.resolution's range: the cost table runs the original scene at each size, and a
    larger bare sheet would only run out of memory)."""
    from .scene import MAX_RESOLUTION

    sizes = [_positive_int(t) for t in text.split(",")]
    if any(not 3 <= n <= MAX_RESOLUTION for n in sizes):
        raise argparse.ArgumentTypeError(
            f"{text!r}: every size must be 3..{MAX_RESOLUTION} particles a side "
            f"(cloth.resolution's range)")
    return sizes


def _fabric_size_list(text: str) -> list[int]:
    """The fabric-cost table's sizes in cells a side, refused before any work unless every
    grid's clips can hold the same length of edge (bench/fabric_cost.py)."""
    from .bench.fabric_cost import size_problem

    sizes = [_positive_int(t) for t in text.split(",")]
    for n in sizes:
        problem = size_problem(n)
        if problem:
            raise argparse.ArgumentTypeError(problem)
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

    about = ("list the fabric presets ([material] preset = \"NAME\") with their values in SI "
             "units and their sources")
    p = sub.add_parser("materials", help=about, description=about[0].upper() + about[1:] + ".")
    p.add_argument("--json", action="store_true", help="print one JSON object (SI base units, "
                                                       "each value's unit given)")

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
                   help="skip the cost-of-accuracy table (the original scene to its tolerance)")
    p.add_argument("--fabric-sizes", type=_fabric_size_list, metavar="N,N,…",
                   help="cells a side of the fabric-cost table (denim held by two clips; "
                        "multiples of 16; default 32,64,128,256; --quick: 16,32)")
    p.add_argument("--no-fabric", action="store_true",
                   help="skip the fabric-cost table (each solver of a material, to its "
                        "tolerance)")

    p = sub.add_parser("accuracy", help="work-precision study of solvers and integrators")
    p.add_argument("--json", action="store_true")
    p.add_argument("--quick", action="store_true", help="a smaller study (under a minute)")
    p.add_argument("--plot", metavar="OUT.png", help="draw the work-precision diagram")
    _add_dask_args(p)

    from .lab.fit_cli import HELP as LAB_FIT_HELP, add_fit_arguments
    from .lab.registry import TESTS as LAB_TESTS  # names only: the tests load when run
    p = sub.add_parser("lab", help="the virtual textile lab: run a standard test on the "
                                   "simulator against its computed expectation, or fit a "
                                   "fabric to measurements")
    p.add_argument("test", help="; ".join([f"{k}: {v[2]}" for k, v in LAB_TESTS.items()]
                                          + [LAB_FIT_HELP]))
    p.add_argument("--material", metavar="NAME",
                   help="a preset of the measured-fabric table (its areal density, stretch, "
                        "shear and bending)")
    p.add_argument("--resolutions", metavar="N,N,…",
                   help="the resolutions to run (what N is depends on the test; default: "
                        "three, coarse to fine)")
    from .sim.solvers import registry as solvers  # names and traits only: no kernels
    lab_solvers = solvers.names(takes_material=True, reference_first=True)
    p.add_argument("--solver", metavar="NAME",
                   help="for the tests of a material (cantilever, peirce, drape): "
                        f"{' or '.join(lab_solvers)} (the first is the default)")
    p.add_argument("--json", action="store_true", help="print one JSON object")
    p.add_argument("--plot", metavar="OUT.png",
                   help="draw the error against resolution and against wall time "
                        "(drape: each run's shadow from above beside the coefficient)")
    add_fit_arguments(p)

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
