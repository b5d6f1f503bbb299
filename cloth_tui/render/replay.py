"""`cloth-tui render BAKE.usd(c/a) -o OUT.png|OUT.mp4|OUT.gif`: draw a bake without
simulating. The points come from the bake's time samples, the objects from its prims, the
rest of the picture (ground, poles, camera) from the scene recorded in it; `--set` may change
only appearance.* keys, since nothing is simulated again.

PNG: the last frame (or frame `--frames`); MP4/GIF: every frame (or the first `--frames`), at
the bake's own frame rate (its timeCodesPerSecond) unless `--fps` says otherwise.
"""

from __future__ import annotations

import sys
from pathlib import Path
from typing import Callable

from ..interrupt import Interrupt, Progress
from ..io.bake_player import bake_model
from ..io.usd_read import UsdBake
from ..safe_text import escape_controls
from ..scene_files import apply_overrides, parse_override
from ..sim.run.run_stats import RunStats
from ..sim.run.runner import Snapshot
from ..usage import UsageError
from .capture import CaptureError, VideoWriter, save_png
from .probe import RendererUnavailable, require_renderer

REPLAY_SECTIONS = ("appearance",)


def bake_scene(bake: UsdBake, overrides: list[str]):
    for text in overrides:
        key, _ = parse_override(text)
        if key.split(".")[0] not in REPLAY_SECTIONS:
            raise UsageError(f"--set {text}: a bake is redrawn, not simulated again; only "
                             f"appearance.* keys can change")
    return apply_overrides(bake.scene, overrides)


def run_replay(args, out: Path, size: tuple[int, int],
               check_textures: Callable[[object], None]) -> int:
    bake = UsdBake(Path(args.scene))
    scene = bake_scene(bake, args.overrides)
    check_textures(scene)  # a damaged texture is bad input, said before any work
    model = bake_model(bake, scene)
    kind = out.suffix.lower()
    frames = bake.frames[:args.frames] if args.frames else bake.frames
    if kind == ".png":
        frames = frames[-1:]
    try:
        require_renderer()
    except RendererUnavailable as e:
        print(escape_controls(f"cloth-tui: error: {e}"), file=sys.stderr)
        return 1

    from .renderer import Renderer

    renderer = Renderer(scene, size)
    progress = Progress(len(frames), sys.stderr.isatty())
    video = None
    done = 0
    try:
        with Interrupt() as interrupt:
            if kind != ".png":
                video = VideoWriter(out, args.fps or bake.frame_rate, size)
            for frame in frames:
                if interrupt.signum is not None:
                    break
                snap = Snapshot(bake.positions(frame), frame, frame / bake.frame_rate, RunStats(),
                                model, scene, bake.objects(frame), bake.alive(frame))
                image = renderer.render(snap)
                if video is not None:
                    video.write(image)
                else:
                    save_png(image, out)
                done += 1
                progress.show(done)
            if video is not None:
                video.close()
        progress.end()
    # The output cannot be written (a full disk, say): exit 2, as for a folder that refuses it.
    except CaptureError as e:
        progress.end()
        if video is not None:
            video.abort()
        print(escape_controls(f"cloth-tui: error: {e}"), file=sys.stderr)
        return 2
    finally:
        renderer.close()
    return interrupt.exit_status(
        done, len(frames),
        f"saved {out} ({done} frames)" if video is not None else "nothing saved")
