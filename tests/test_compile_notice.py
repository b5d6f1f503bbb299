"""A first run says it is compiling kernels (numba's cache is empty), and with what progress;
a run whose kernels load from the cache says nothing."""

import io
import os
import subprocess
import sys
import time

from numba import njit

from cloth_tui.compile_notice import HEADER, CompileNotice


def _fresh_kernels():
    """Two kernels never compiled in this process (no cache): each call compiles one."""
    @njit
    def inner(x):
        return x * 2.0

    @njit
    def outer(x):
        return inner(x) + 1.0

    return outer, inner


def test_compiling_is_announced_with_a_count_and_ended():
    outer, inner = _fresh_kernels()
    out = io.StringIO()
    with CompileNotice(out, live=True) as notice:
        outer(1.0)  # compiles outer and, nested within it, inner
        notice.finish()
        outer(2.0)  # compiled already: nothing more
    text = out.getvalue()
    assert text.startswith(HEADER) and text.endswith("\n") and text.count("\n") == 1
    assert "1 compiled" in text and notice.compiled == 1  # one kernel compiled at the top


def test_nothing_compiled_nothing_said():
    outer, _ = _fresh_kernels()
    outer(1.0)
    out = io.StringIO()
    with CompileNotice(out, live=False):
        outer(3.0)
    assert out.getvalue() == ""


def test_not_a_terminal_gets_whole_lines():
    outer, _ = _fresh_kernels()
    out = io.StringIO()
    with CompileNotice(out, live=False):
        outer(1.0)
    lines = out.getvalue().splitlines()
    assert lines[0] == HEADER and "1 kernels compiled" in lines[1] and len(lines) == 2


def test_a_first_render_says_so_before_it_compiles(tmp_path):
    """With an empty kernel cache, `render` says so at once (the compiling that follows
    takes ~30 s: the test stops the run once the line is there)."""
    env = dict(os.environ, NUMBA_CACHE_DIR=str(tmp_path / "cache"))
    run = subprocess.Popen([sys.executable, "-m", "cloth_tui", "render", "default", "-o",
                            str(tmp_path / "out.png"), "--frames", "1", "--size", "64x48"],
                           stderr=subprocess.PIPE, stdout=subprocess.DEVNULL, env=env,
                           text=True)
    try:
        deadline = time.monotonic() + 120
        line = ""
        while time.monotonic() < deadline:
            line = run.stderr.readline()
            if not line or HEADER in line:
                break
        assert HEADER in line, line
    finally:
        run.kill()
        run.wait()


def test_the_apps_watch_counts_kernels_compiled_on_any_thread_and_falls_silent():
    import threading

    from cloth_tui.compile_notice import CompileWatch

    outer, inner = _fresh_kernels()
    with CompileWatch() as watch:
        assert watch.describe() == ""  # nothing compiled yet: nothing said
        worker = threading.Thread(target=outer, args=(1.0,))  # as the simulation thread
        worker.start()
        worker.join()
        said = watch.describe()
        assert said.startswith("compiling kernels (first run only)… 1 compiled")
        later = time.monotonic() + CompileWatch.LINGER_S + 0.1
        assert watch.describe(now=later) == ""  # done: the status line goes back
        outer(2.0)  # cached in the process: no event, still silent
        assert watch.describe(now=later) == "" and watch.compiled == 1
    watch.__exit__(None, None, None)  # a second exit (the app's shutdown) is harmless


def test_a_later_phase_of_compiling_counts_from_its_own_start(monkeypatch):
    # Turning wind on a minute in compiles its kernel then: the status line says "1 compiled,
    # 0 s", not the session's count and the time since its first compile.
    import cloth_tui.compile_notice as notice
    from cloth_tui.compile_notice import CompileWatch

    clock = [100.0]
    monkeypatch.setattr(notice.time, "monotonic", lambda: clock[0])
    watch = CompileWatch()  # events fed by hand: no numba listener needed
    for _ in range(3):  # the first run's kernels
        watch._on_start()
        clock[0] += 10.0
        watch._on_end()
    assert watch.describe().endswith("3 compiled, 30 s")
    clock[0] += 60.0
    assert watch.describe() == ""
    watch._on_start()  # the wind's kernel
    clock[0] += 2.0
    assert watch.describe().endswith("0 compiled, 2 s")
    watch._on_end()
    assert watch.describe().endswith("1 compiled, 2 s") and watch.compiled == 4
