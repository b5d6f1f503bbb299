"""Command line: dispatch to the command, inside one guard. Heavy modules (numba, vtk,
textual) load lazily, in the command that needs them, so `cloth-tui --help` answers at once.

Exit status: 0 success, 2 bad input (one line on stderr), 130 Ctrl+C (one line), 1 anything
unexpected.

Only `os` and `sys` (loaded before any script runs) are imported at the top: every other
import, the parsers' included, happens inside `main`'s guard, so Ctrl+C while modules load is
the same one line as Ctrl+C in the middle of a run. Before the guard, from the package's first
line, `cloth_tui.end_at_start_up` gives the same line and status (the interpreter's own
start-up, `site` and its `.pth` files, runs before any line of the package can).
"""

from __future__ import annotations

import os
import sys


def cmd_scenes(args) -> int:
    from .resources import builtin_scenes
    for name, path in builtin_scenes().items():
        first = path.read_text(encoding="utf-8").splitlines()[0:1]
        doc = first[0].lstrip("# ").strip() if first and first[0].startswith("#") else ""
        print(f"{name:<20} {doc}")
    return 0


def cmd_materials(args) -> int:
    from .materials.cli import run_materials
    return run_materials(args)


def cmd_simulate(args) -> int:
    import json
    from pathlib import Path

    import numpy as np

    from .scene_files import apply_overrides, load
    from .usage import check_output_path

    scene = apply_overrides(load(args.scene), args.overrides)
    if args.dump:
        check_output_path(Path(args.dump), (".npz",))
    from .compile_notice import CompileNotice
    from .interrupt import mesh_grid_progress
    from .sim.run.runner import Simulation

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
    from pathlib import Path

    from .scene_files import apply_overrides, load

    if Path(args.scene).suffix.lower() in (".usd", ".usdc", ".usda"):  # a bake: replay it
        from .tui.replay_app import run_replay_app
        return run_replay_app(Path(args.scene), args.overrides, Path(args.captures),
                              graphics=_detect_graphics(args))
    scene = apply_overrides(load(args.scene), args.overrides)
    _build_mesh_grids(scene)
    graphics = _detect_graphics(args)
    from .tui.app import run_app
    from .tui.graphics.detect import in_browser
    return run_app(scene, Path(args.captures), graphics=graphics,
                   start_when_shown=in_browser(os.environ))


def _build_mesh_grids(scene) -> None:
    """Build the mesh objects' distance grids (cached) before the app takes the terminal:
    their progress shows on it, and a bad mesh file is one line, as for any command."""
    if not any(o.type == "mesh" for o in scene.objects):
        return
    from .interrupt import mesh_grid_progress
    from .sim.collision.colliders import build_colliders
    from .sim.model import build_model

    with mesh_grid_progress(sys.stderr.isatty()):
        build_colliders(scene, build_model(scene.cloth, scene.behavior))


def _detect_graphics(args):
    from .tui.graphics.detect import detect  # before Textual takes the terminal
    return detect(args.graphics)


def _check_thread_limit() -> None:
    from .sim.threads import env_threads
    from .usage import UsageError
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
    """Run the command in `argv` (default: the process's own arguments) and return its exit
    status. Called without `argv` it is the process's command line, and also guards the
    interpreter's shutdown after it: Ctrl+C there is the same one line and 130."""
    import signal

    from . import end_at_start_up

    global _interrupt_seen
    _interrupt_seen = False
    command_line = argv is None
    # Only where Python's own handler (or the package's until now) is in place: a process
    # started with SIGINT ignored (a background job, nohup) keeps ignoring it; off the main
    # thread nothing can be set.
    ours = (_on_main_thread() and signal.getsignal(signal.SIGINT) in
            (signal.default_int_handler, end_at_start_up))
    unraisable_hook = sys.unraisablehook
    try:
        if ours:
            signal.signal(signal.SIGINT, _raise_interrupt)
            sys.unraisablehook = _interrupt_again(unraisable_hook)
        status = _run(sys.argv[1:] if argv is None else list(argv))
        if _interrupt_seen:  # raised where a library ignored it, before it came again
            status = None
    except KeyboardInterrupt:
        status = None
    except Exception:
        # Ctrl+C that Python or a library turned into an error of its own where _run's own
        # check cannot see it (Python 3.11 wraps it in a RuntimeError when it lands in a
        # class body's __set_name__, as the parsers' modules load)
        if not _interrupt_seen:
            raise
        status = None
    finally:
        sys.unraisablehook = unraisable_hook
        for again in _sent_again:
            again.cancel()
        if ours and not command_line:
            signal.signal(signal.SIGINT, signal.default_int_handler)
    if ours and command_line:  # a second Ctrl+C while this is said is quiet
        _exit_on_interrupt(say_it=status is not None)
    if status is None:
        print("cloth-tui: interrupted", file=sys.stderr)
        return 130
    return status


# Set by the SIGINT handler: a library may turn the KeyboardInterrupt into an error of its own
# (NumPy's import into "Importing the numpy C-extensions failed"), which is Ctrl+C all the same.
_interrupt_seen = False


# The SIGINTs _interrupt_again has yet to send: main's end cancels them.
_sent_again: list = []


def _interrupt_again(hook):
    """sys.unraisablehook within main's guard: a KeyboardInterrupt that a library's callback
    cannot raise (llvmlite's, as numba loads a cached kernel: "Exception ignored on calling
    ctypes callback function", and the work went on) is sent again as SIGINT, for the guard's
    handler to raise where the work is; anything else goes to `hook`. It is sent from another
    thread a moment later: sent here, the handler would raise it inside this hook, where it
    is ignored too. (Landing in a callback again, it comes back here and is sent again.)"""
    def on_unraisable(unraisable):
        if isinstance(unraisable.exc_value, KeyboardInterrupt):
            import signal
            import threading
            again = threading.Timer(0.01, os.kill, (os.getpid(), signal.SIGINT))
            again.daemon = True
            _sent_again.append(again)
            again.start()
            return
        hook(unraisable)
    return on_unraisable


def _raise_interrupt(_signum, _frame):
    global _interrupt_seen
    _interrupt_seen = True
    raise KeyboardInterrupt


def _hand_back_sigint() -> None:
    """Python's own SIGINT handler again, for the app and serve: asyncio's runner turns
    Ctrl+C into cancelling its main task only where it finds that handler in place."""
    import signal

    if signal.getsignal(signal.SIGINT) is _raise_interrupt:
        signal.signal(signal.SIGINT, signal.default_int_handler)


def _on_main_thread() -> bool:
    import threading
    return threading.current_thread() is threading.main_thread()


def _exit_on_interrupt(say_it: bool) -> None:
    """From now on Ctrl+C ends the process at once with 130 (and the one line if `say_it`):
    after the command's work only the interpreter's shutdown is left, where a
    KeyboardInterrupt would print a traceback from whatever shutdown code was running."""
    import signal

    def _exit(_signum, _frame):
        if say_it:
            os.write(2, b"cloth-tui: interrupted\n")
        os._exit(130)

    signal.signal(signal.SIGINT, _exit)


# The commands whose result is what they print: with stdout closed they are refused before
# any work. (render and bake write files; serve's stdout is a log, and a log line that cannot
# be written must not stop a server; the app draws on the terminal, not on stdout.)
PRINTING_COMMANDS = ("simulate", "scenes", "materials", "bench", "accuracy", "lab", "wedge")


def _run(argv: list[str]) -> int:
    os.environ.setdefault(BLAS_THREADS_ENV, "1")
    from .cli_args import COMMANDS, build_parsers
    from .safe_text import escape_controls
    from .std_output import CLOSED, CheckedOutput, OutputError, discard_unwritten

    app_parser, cmd_parser = build_parsers()
    stdout = sys.stdout
    sys.stdout = CheckedOutput(stdout)
    try:
        _check_thread_limit()
        if argv and argv[0] in COMMANDS:
            if stdout is None and argv[0] in PRINTING_COMMANDS:
                raise OutputError(CLOSED)
            args = _parse(cmd_parser, argv)
            handler = globals()[f"cmd_{args.command}"] if args is not None else None
        else:
            args = _parse(app_parser, argv)
            handler = cmd_app if args is not None else None
        if handler in (cmd_app, cmd_serve):  # their stdout as it is (PRINTING_COMMANDS)
            sys.stdout = stdout
            _hand_back_sigint()
        status = handler(args) if handler is not None else 0
        sys.stdout.flush()  # a result still buffered fails here, inside the guard
        return status
    except BrokenPipeError:  # the reader has what it wanted (`| head`)
        discard_unwritten(stdout)
        return 0
    except Exception as e:
        if _interrupt_seen:
            raise KeyboardInterrupt from None
        if isinstance(e, OutputError):
            discard_unwritten(stdout)
        if _is_bad_input(e):
            message = f"cloth-tui: error: {e}".replace("cloth-tui: error: cloth-tui",
                                                       "cloth-tui")
            print(escape_controls(message), file=sys.stderr)
            return 2
        # a bug, not bad input: keep the details, show one line
        import tempfile
        import traceback
        fd, log = tempfile.mkstemp(prefix="cloth-tui-crash-", suffix=".log")
        with os.fdopen(fd, "w") as fh:
            traceback.print_exc(file=fh)
        print(escape_controls(f"cloth-tui: internal error: {type(e).__name__}: {e} "
                              f"(traceback in {log})"), file=sys.stderr)
        return 1
    finally:
        sys.stdout = stdout


def _parse(parser, argv: list[str]):
    """The parsed arguments, or None where --help or --version has printed all there was
    to do (argparse ends those with SystemExit, which would skip the flush that checks the
    output was written)."""
    try:
        return parser.parse_args(argv)
    except SystemExit as e:
        if e.code not in (0, None):
            raise
        return None


def _is_bad_input(e: Exception) -> bool:
    """A UsageError or SceneError. The scene module (and NumPy with it) is not loaded to ask:
    where it never loaded, no SceneError was raised, and `--help` stays fast."""
    from .usage import UsageError
    scene = sys.modules.get("cloth_tui.scene")
    return isinstance(e, UsageError) or (scene is not None and isinstance(e, scene.SceneError))
