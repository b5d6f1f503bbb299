"""Dots on the held particles: in a renderer made with markers (the app's), on every held
particle (pins, soft pins, a pinned grab), and off with appearance.show_pins = false."""

import numpy as np
import pytest

from cloth_tui import scene_files as sf
from cloth_tui.render.pin_markers import held_particles
from cloth_tui.render.renderer import Renderer
from cloth_tui.sim.model import build_model
from cloth_tui.sim.effects.pins import with_user_pin

from .helpers import draped, scene_with


def yellow_pixels(img: np.ndarray) -> int:
    r, g, b = (img[..., k].astype(int) for k in range(3))
    return int(((r > 200) & (g > 170) & (b < 90)).sum())


@pytest.fixture(scope="module")
def marked():
    r = Renderer(scene_with(), (240, 180), markers=True)
    yield r
    r.close()


def test_markers_show_the_pins_and_turn_off(marked, renderer):
    on = draped(scene_with())
    assert yellow_pixels(marked.render(on)) >= 4 * 4  # four corners, a few pixels each
    assert yellow_pixels(marked.render(draped(scene_with(show_pins=False)))) == 0
    assert yellow_pixels(renderer.render(draped(scene_with()))) == 0  # `render`'s pictures


def test_more_held_particles_make_more_dots(marked):
    corners = yellow_pixels(marked.render(draped(scene_with())))
    edge = scene_with().with_value("cloth.pinned", "one_edge")
    assert yellow_pixels(marked.render(draped(edge))) > 3 * corners


def test_held_particles_cover_soft_pins_and_grabs():
    s = sf.apply_overrides(scene_with(), ["cloth.resolution=6", "cloth.pinned=none",
                                          "pins=[{at=[[0,0]]}, {at=[[2,2]], stiffness=0.5}]"])
    model = build_model(s.cloth, s.behavior, s.pins)
    assert list(held_particles(model)) == [0, 14]
    grabbed, _ = with_user_pin(model, 20, [0.0, 0.3, 0.0])
    assert list(held_particles(grabbed)) == [0, 14, 20]
