"""Importing PyVista/VTK for off-screen use: EGL window (no X display needed) and no VTK
chatter on the terminal, which would corrupt a full-screen TUI. Every render module gets
pyvista through `pyvista_quiet()` so these settings are made before the first import."""

from __future__ import annotations

import os

OPENGL_WINDOW_ENV = "VTK_DEFAULT_OPENGL_WINDOW"
OPENGL_WINDOW_DEFAULT = "vtkEGLRenderWindow"  # off-screen through EGL: no X display needed
_ready = False


def pyvista_quiet():
    global _ready
    os.environ.setdefault(OPENGL_WINDOW_ENV, OPENGL_WINDOW_DEFAULT)
    import pyvista as pv
    if not _ready:
        from vtkmodules.vtkCommonCore import vtkLogger, vtkObject, vtkOutputWindow

        vtkObject.GlobalWarningDisplayOff()
        vtkLogger.SetStderrVerbosity(vtkLogger.VERBOSITY_OFF)
        # Anything that still reaches the output window goes nowhere, not to stderr.
        vtkOutputWindow.GetInstance().SetDisplayModeToNever()
        try:
            pv.vtk_verbosity("off")
        except (AttributeError, TypeError, ValueError):
            pass
        pv.OFF_SCREEN = True
        pv.global_theme.allow_empty_mesh = True  # objects/poles start empty, filled in place
        _ready = True
    return pv
