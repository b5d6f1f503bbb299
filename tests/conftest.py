import contextlib
import io
import os

import pytest
from hypothesis import settings

# Off-screen rendering through EGL; no X display on CI.
os.environ.setdefault("VTK_DEFAULT_OPENGL_WINDOW", "vtkEGLRenderWindow")

# Hypothesis's default deadline (200 ms an example) is a wall-clock assertion: on a loaded
# machine a refusal of 3,929 nested brackets took 473 ms once and 3 ms when rerun, and the
# test failed as flaky. The tests assert behaviour; how long an example takes is not theirs.
settings.register_profile("cloth-tui", deadline=None)
settings.load_profile("cloth-tui")


def pytest_collection_modifyitems(config, items):
    """The tests marked `heavy` first, the rest in their order: the workers take tests in
    this order, so the long ones start together and the short ones fill in after them,
    rather than one long test running alone at the end."""
    items.sort(key=lambda item: item.get_closest_marker("heavy") is None)


@pytest.fixture(scope="session", autouse=True)
def kernels_compiled(tmp_path_factory):
    """Each test process compiles (or loads from numba's cache) the kernels of a render before
    its first test. A first run's "compiling kernels" lines are right for a user, but a test
    of what stderr says would count them: which test runs first in a worker is not fixed."""
    from cloth_tui.cli import main

    out = tmp_path_factory.mktemp("warm") / "warm.png"
    with contextlib.redirect_stderr(io.StringIO()), contextlib.redirect_stdout(io.StringIO()):
        # no GL here is not this fixture's failure: the tests that need it say so
        main(["render", "default", "-o", str(out), "--frames", "2", "--size", "64x48"])
