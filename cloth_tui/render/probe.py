"""Can this machine render off-screen? Asked once per process, in a short child process,
because without a working EGL/OpenGL driver VTK does not raise: it kills the whole process
with SIGSEGV (seen with `__EGL_VENDOR_LIBRARY_FILENAMES=/nonexistent.json`, where VTK falls
back from EGL to OSMesa and crashes in its first render). Nothing here imports VTK."""

from __future__ import annotations

import ctypes.util
import functools
import glob
import os
import signal
import subprocess
import sys

from .vtk_setup import OPENGL_WINDOW_DEFAULT, OPENGL_WINDOW_ENV

# Debian packages: libEGL.so.1 (glvnd), Mesa's EGL vendor library and its drivers.
INSTALL_HINT = "install the Debian packages libegl1, libegl-mesa0 and libgl1-mesa-dri"
PROBE_TIMEOUT_S = 60.0  # a cold start (VTK import, Mesa's shader compiler) takes about 0.5 s
EGL_VENDOR_DIRS = ("/etc/glvnd/egl_vendor.d", "/usr/share/glvnd/egl_vendor.d")

# The child: open an 8×8 off-screen window the way the renderer does and draw once.
_PROBE_CODE = """
import resource
resource.setrlimit(resource.RLIMIT_CORE, (0, 0))  # an expected crash leaves no core file
from vtkmodules.vtkCommonCore import vtkLogger, vtkObject
vtkObject.GlobalWarningDisplayOff()
vtkLogger.SetStderrVerbosity(vtkLogger.VERBOSITY_OFF)
import vtkmodules.vtkRenderingOpenGL2
from vtkmodules.vtkRenderingCore import vtkRenderer, vtkRenderWindow
window = vtkRenderWindow()
print(window.GetClassName(), flush=True)
window.SetOffScreenRendering(1)
window.SetSize(8, 8)
window.AddRenderer(vtkRenderer())
window.Render()
window.Finalize()
print("ok", flush=True)
"""


class RendererUnavailable(RuntimeError):
    """No off-screen OpenGL here. The message is one line: what failed, what seems missing,
    and which packages to install."""


def require_renderer() -> None:
    """Raise RendererUnavailable unless a child process could render off-screen."""
    problem = renderer_problem()
    if problem is not None:
        raise RendererUnavailable(problem)


@functools.cache
def renderer_problem() -> str | None:
    """None if off-screen rendering works here, else the one-line reason (cached: the
    driver does not change while the process runs)."""
    env = dict(os.environ)
    env.setdefault(OPENGL_WINDOW_ENV, OPENGL_WINDOW_DEFAULT)
    try:
        child = subprocess.run([sys.executable, "-c", _PROBE_CODE], env=env,
                               stdin=subprocess.DEVNULL, capture_output=True, text=True,
                               timeout=PROBE_TIMEOUT_S)
    except subprocess.TimeoutExpired:
        return _explain(f"the OpenGL renderer did not start within {PROBE_TIMEOUT_S:.0f} s")
    except OSError as e:
        return f"no off-screen renderer: cannot start the probe: {e.strerror or e}"
    lines = child.stdout.split()
    if child.returncode == 0 and lines[-1:] == ["ok"]:
        return None
    window = f" ({lines[0]})" if lines and lines[0] != "ok" else ""
    if child.returncode < 0:
        name = signal.Signals(-child.returncode).name
        return _explain(f"the OpenGL renderer{window} crashed while starting ({name})")
    err = [ln for ln in child.stderr.strip().splitlines() if ln.strip()]
    detail = err[-1].strip() if err else f"exit status {child.returncode}"
    return _explain(f"the OpenGL renderer{window} failed to start: {detail}")


def _explain(what: str) -> str:
    missing = missing_libraries()
    found = f"; missing: {', '.join(missing)}" if missing else ""
    return f"no off-screen renderer: {what}{found}; {INSTALL_HINT}"


def missing_libraries() -> list[str]:
    """What EGL needs and this machine seems to lack (best effort, by looking at files)."""
    missing = []
    if ctypes.util.find_library("EGL") is None:
        missing.append("libEGL.so.1 (libegl1)")
    named = os.environ.get("__EGL_VENDOR_LIBRARY_FILENAMES")
    if named is not None:
        if not any(os.path.isfile(f) for f in named.split(":") if f):
            missing.append(f"an EGL vendor library (__EGL_VENDOR_LIBRARY_FILENAMES={named} "
                           "names no existing file)")
    else:
        dirs = os.environ.get("__EGL_VENDOR_LIBRARY_DIRS", ":".join(EGL_VENDOR_DIRS))
        if not any(glob.glob(os.path.join(d, "*.json")) for d in dirs.split(":") if d):
            missing.append("an EGL vendor library (libegl-mesa0)")
    return missing
