import pytest

from cloth_tui.render.renderer import Renderer

from .helpers import scene_with


@pytest.fixture(scope="module")
def renderer():
    """One renderer per module: making a GL context costs ~0.5 s; tests restore settings."""
    r = Renderer(scene_with(), (160, 120))
    yield r
    r.close()
