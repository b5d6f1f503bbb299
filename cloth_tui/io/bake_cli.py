"""`cloth-tui bake SCENE -o OUT [--frames N] [--set ...]`: simulate headless and write every
frame: OUT.usd/.usdc/.usda (USD, see usd_bake) or OUT_####.obj/.ply (one mesh per frame).

SIGINT/SIGTERM stop after the current frame and finish the file properly (exit 130/143); a
SIGKILL leaves the frames of the last save (USD) or every finished frame (OBJ/PLY).
"""

from __future__ import annotations

import os
import re
import sys
from pathlib import Path

from ..interrupt import Interrupt, Progress, mesh_grid_progress
from ..safe_text import escape_controls
from ..scene_files import apply_overrides, load
from ..usage import UsageError, check_output_path
from .frames import BakedFrame, BakeWriter
from .mesh_sequence import SEQUENCE_SUFFIXES, BakeIOError, MeshSequenceWriter, sequence_path
from .usd_bake import USD_SUFFIXES, UsdBakeWriter, missing_usd_message

BAKE_SUFFIXES = USD_SUFFIXES + SEQUENCE_SUFFIXES
DEFAULT_FRAMES = 120
TEMP_NAME_EXTRA = 15  # util.atomic_write's temporary name: "." + name + ".1a2b3c4d.part"


def name_max(folder: Path) -> int:
    """The longest file name (bytes) the folder's file system takes."""
    try:
        return os.pathconf(folder if str(folder) else ".", "PC_NAME_MAX")
    except (OSError, ValueError):
        return 255


def open_writer(out: Path, scene, model) -> BakeWriter:
    if out.suffix.lower() in USD_SUFFIXES:
        return UsdBakeWriter(out, scene, model)
    return MeshSequenceWriter(out, model)


def check_bake_output(out: Path, frames: int) -> None:
    """Bad output, said before any work: a wrong type, a folder that cannot take the file,
    USD without usd-core, or frame files whose names the folder cannot take (too long, or
    an existing folder of that name)."""
    check_output_path(out, BAKE_SUFFIXES)
    if out.suffix.lower() in USD_SUFFIXES:
        message = missing_usd_message()
        if message:
            raise UsageError(message)
        return
    last = sequence_path(out, frames)
    limit = name_max(last.parent)
    if len(os.fsencode(last.name)) + TEMP_NAME_EXTRA > limit:
        raise UsageError(f"{out}: its frame files' names ({len(last.name)} characters) are "
                         f"too long: this folder takes names of at most {limit} bytes, "
                         f"{TEMP_NAME_EXTRA} of them for the temporary name")
    taken = folder_frame(out, frames)
    if taken is not None:
        raise UsageError(f"{sequence_path(out, taken)}: is a folder; the bake would write "
                         f"frame {taken} there")


def folder_frame(out: Path, frames: int) -> int | None:
    """The first of frames 1..frames whose file name is an existing folder, or None (one
    listing of the folder, not a look-up per frame)."""
    folder = out.parent if str(out.parent) else Path(".")
    try:
        names = [e.name for e in os.scandir(folder) if e.is_dir()]
    except OSError:
        return None
    hits = [k for name in names for k in map(int, re.findall(r"\d+", name))
            if 1 <= k <= frames and sequence_path(out, k).name == name]
    return min(hits, default=None)


def run_bake(args) -> int:
    out = Path(args.output)
    frames = args.frames or DEFAULT_FRAMES
    check_bake_output(out, frames)
    scene = apply_overrides(load(args.scene), args.overrides)

    from ..sim.run.run_stats import RunStats
    from ..sim.run.runner import Simulation

    with mesh_grid_progress(sys.stderr.isatty()):
        sim = Simulation(scene)
    writer = open_writer(out, scene, sim.model)
    progress = Progress(frames, sys.stderr.isatty(), label="baking")
    done = 0
    try:
        with Interrupt() as interrupt:
            for frame in range(1, frames + 1):
                if interrupt.signum is not None:
                    break
                sim.advance_frame()
                snap = sim.snapshot(stats=RunStats())
                writer.write(BakedFrame(frame, snap.t, snap.positions, snap.objects,
                                        snap.alive))
                done = frame
                progress.show(done)
            writer.close()
    except BakeIOError as e:  # a full disk, say: the output cannot be written, as exit 2 says
        progress.end()
        print(escape_controls(f"cloth-tui: error: {e}"), file=sys.stderr)
        return 2
    progress.end()
    where = out if out.suffix.lower() in USD_SUFFIXES else \
        f"{sequence_path(out, 1)} … {sequence_path(out, max(1, done)).name}"
    return interrupt.exit_status(done, frames, f"saved {where}")
