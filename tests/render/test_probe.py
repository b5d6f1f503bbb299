"""The renderer is probed in a child process: a missing EGL/OpenGL driver gives one clear
line and exit status 1, never a segfault of the user's process."""

import os
import subprocess
import sys

import pytest

from cloth_tui.render import probe
from cloth_tui.scene import Scene

NO_EGL = {"__EGL_VENDOR_LIBRARY_FILENAMES": "/nonexistent.json"}


@pytest.fixture
def fresh_probe():
    probe.renderer_problem.cache_clear()
    yield
    probe.renderer_problem.cache_clear()


def test_probe_finds_the_renderer_here(fresh_probe):
    assert probe.renderer_problem() is None


def test_renderer_raises_a_one_line_reason_instead_of_crashing(monkeypatch, fresh_probe):
    from cloth_tui.render.renderer import Renderer
    monkeypatch.setenv("__EGL_VENDOR_LIBRARY_FILENAMES", "/nonexistent.json")
    with pytest.raises(probe.RendererUnavailable) as err:
        Renderer(Scene(), (32, 24))
    text = str(err.value)
    assert "\n" not in text and "__EGL_VENDOR_LIBRARY_FILENAMES" in text
    assert "libegl1" in text and "libegl-mesa0" in text and "libgl1-mesa-dri" in text


def _cli(tmp_path, *args):
    env = dict(os.environ, **NO_EGL)
    return subprocess.run([sys.executable, "-m", "cloth_tui", *args], capture_output=True,
                          text=True, env=env, cwd=tmp_path, timeout=300)


def test_render_without_egl_exits_1_with_one_line(tmp_path):
    p = _cli(tmp_path, "render", "default", "-o", "x.png")
    assert p.returncode == 1, (p.returncode, p.stderr)  # not -11 (SIGSEGV)
    lines = p.stderr.strip().splitlines()
    assert len(lines) == 1 and "Traceback" not in p.stderr
    assert lines[0].startswith("cloth-tui: error: no off-screen renderer")
    assert "libegl-mesa0" in lines[0]
    assert not (tmp_path / "x.png").exists()
    assert not list(tmp_path.glob("core*"))


def test_simulate_needs_no_renderer(tmp_path):
    p = _cli(tmp_path, "simulate", "sphere", "--frames", "10", "--json")
    assert p.returncode == 0, p.stderr
