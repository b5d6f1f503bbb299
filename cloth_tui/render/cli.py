"""`cloth-tui render SCENE -o OUT.png|OUT.mp4|OUT.gif`: simulate headless and draw.

PNG: the last of `--frames` frames (default: 2 s of simulated time, 2·frame_rate frames, so the
sheet has settled). MP4/GIF: every frame (default 90); a GIF at most capture.GIF_MAX_PIXELS pixels
over all frames. SIGINT/SIGTERM finish the video properly (playable file, final name) and exit
130/143. A bake (SCENE.usd/.usdc/.usda) is drawn from its frames, without simulating: see replay.py.
"""

from __future__ import annotations

import re
import sys
from pathlib import Path

from ..compile_notice import CompileNotice
from ..interrupt import Interrupt as _Interrupt
from ..interrupt import Progress as _Progress
from ..interrupt import mesh_grid_progress
from ..io.usd_bake import USD_SUFFIXES
from ..safe_text import escape_controls
from ..scene_files import apply_overrides, load
from ..usage import UsageError, check_output_path
from .capture import CaptureError, VideoWriter, gif_max_frames, save_png
from .probe import RendererUnavailable, require_renderer
from .renderer import MAX_SIZE

OUTPUT_SUFFIXES = (".png", ".mp4", ".gif")
SETTLE_S = 2.0       # s of simulated time before a PNG is taken: the sheet has draped
VIDEO_FRAMES = 90


def parse_size(text: str) -> tuple[int, int]:
    m = re.fullmatch(r"\s*(\d+)\s*[xX×]\s*(\d+)\s*", str(text))
    if not m:
        raise UsageError(f"--size {text!r}: expected WIDTHxHEIGHT, e.g. 640x480")
    w, h = int(m.group(1)), int(m.group(2))
    if not (1 <= w <= MAX_SIZE and 1 <= h <= MAX_SIZE):
        raise UsageError(f"--size {text!r}: each side must be 1..{MAX_SIZE} pixels")
    return w, h


def default_frames(kind: str, scene) -> int:
    """A PNG shows the sheet settled (SETTLE_S of simulated time), not its flat first frame;
    a video shows its first VIDEO_FRAMES frames."""
    if kind == ".png":
        return max(1, round(SETTLE_S * scene.behavior.frame_rate))
    return VIDEO_FRAMES


def _check_textures(scene) -> None:
    """Decode the scene's textures once up front: a file that passed the scene's header check
    but cannot be decoded (truncated, damaged) is bad input, reported before any work."""
    from .textures import TextureError, load_texture_image

    for name in (scene.appearance.cloth_texture, scene.appearance.ground_texture):
        try:
            load_texture_image(name)
        except TextureError as e:
            raise UsageError(str(e)) from None


def run_render(args) -> int:
    out = Path(args.output)
    check_output_path(out, OUTPUT_SUFFIXES)
    size = parse_size(args.size)
    if Path(args.scene).suffix.lower() in USD_SUFFIXES:  # a bake: draw it, simulate nothing
        from .replay import run_replay
        return run_replay(args, out, size, check_textures=_check_textures)
    scene = apply_overrides(load(args.scene), args.overrides)
    _check_textures(scene)
    kind = out.suffix.lower()
    frames = args.frames or default_frames(kind, scene)
    fps = getattr(args, "fps", 30) or 30
    if kind == ".gif" and frames > gif_max_frames(size):
        raise UsageError(f"{out}: a GIF holds every frame in memory: at most "
                         f"{gif_max_frames(size)} frames at {size[0]}x{size[1]} "
                         f"(fewer --frames, a smaller --size, or .mp4)")
    try:
        require_renderer()  # before simulating: a missing driver is said at once
    except RendererUnavailable as e:
        print(f"cloth-tui: error: {e}", file=sys.stderr)
        return 1

    from ..sim.run.runner import Simulation
    from .renderer import Renderer

    with mesh_grid_progress(sys.stderr.isatty()):
        sim = Simulation(scene)
    renderer = Renderer(scene, size)
    progress = _Progress(frames, sys.stderr.isatty())
    video = None
    done = 0
    try:
        with _Interrupt() as interrupt, CompileNotice(sys.stderr, progress.enabled) as notice:
            if kind != ".png":
                video = VideoWriter(out, fps, size)
            # The drawing's kernels compile here (the camera kept), the simulation's in the
            # first frame: a first run's compiling is over before the progress bar starts.
            renderer.render(sim.snapshot(), auto_rotate_deg=0.0)
            for done in range(1, frames + 1):
                if interrupt.signum is not None:
                    done -= 1
                    break
                sim.advance_frame()
                if video is not None:
                    video.write(renderer.render(sim.snapshot()))
                notice.finish()  # the first frame compiled what a frame needs
                progress.show(done)
            if kind == ".png" and interrupt.signum is None:
                save_png(renderer.render(sim.snapshot()), out)
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
        done, frames, f"saved {out} ({done} frames)" if video is not None else "nothing saved")
