"""`cloth-tui bake SCENE -o OUT [--frames N] [--set ...]`: simulate headless and write every
frame: OUT.usd/.usdc/.usda (USD, see usd_bake) or OUT_####.obj/.ply (one mesh per frame).

SIGINT/SIGTERM stop after the current frame and finish the file properly (exit 130/143); a
SIGKILL leaves the frames of the last save (USD) or every finished frame (OBJ/PLY).
"""

from __future__ import annotations

import sys
from pathlib import Path

from ..interrupt import Interrupt, Progress
from ..safe_text import escape_controls
from ..scene_files import apply_overrides, load
from ..usage import UsageError, check_output_path
from .frames import BakedFrame, BakeWriter
from .mesh_sequence import SEQUENCE_SUFFIXES, BakeIOError, MeshSequenceWriter, sequence_path
from .usd_bake import USD_SUFFIXES, UsdBakeWriter, missing_usd_message

BAKE_SUFFIXES = USD_SUFFIXES + SEQUENCE_SUFFIXES
DEFAULT_FRAMES = 120


def open_writer(out: Path, scene, model) -> BakeWriter:
    if out.suffix.lower() in USD_SUFFIXES:
        return UsdBakeWriter(out, scene, model)
    return MeshSequenceWriter(out, model)


def check_bake_output(out: Path) -> None:
    """Bad output, said before any work: a wrong type, a folder that cannot take the file,
    or USD without usd-core."""
    check_output_path(out, BAKE_SUFFIXES)
    if out.suffix.lower() in USD_SUFFIXES:
        message = missing_usd_message()
        if message:
            raise UsageError(message)


def run_bake(args) -> int:
    out = Path(args.output)
    check_bake_output(out)
    scene = apply_overrides(load(args.scene), args.overrides)
    frames = args.frames or DEFAULT_FRAMES

    from ..sim.runner import Simulation

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
                snap = sim.snapshot(stats={})
                writer.write(BakedFrame(frame, snap.t, snap.positions, snap.objects,
                                        snap.alive))
                done = frame
                progress.show(done)
            writer.close()
    except BakeIOError as e:
        progress.end()
        print(escape_controls(f"cloth-tui: error: {e}"), file=sys.stderr)
        return 1
    progress.end()
    where = out if out.suffix.lower() in USD_SUFFIXES else \
        f"{sequence_path(out, 1)} … {sequence_path(out, max(1, done)).name}"
    return interrupt.exit_status(done, frames, f"saved {where}")
