import os

# Off-screen rendering through EGL; no X display on CI.
os.environ.setdefault("VTK_DEFAULT_OPENGL_WINDOW", "vtkEGLRenderWindow")
