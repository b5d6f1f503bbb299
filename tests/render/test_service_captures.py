"""The render service's recordings when the simulation sends nothing new: a paused sheet is
recorded as its still picture; a recording with no picture at all leaves no file. A texture
that cannot be drawn gives a notice and an untextured cloth, never a dead renderer."""

import numpy as np
import pytest

from cloth_tui.render.service import CaptureKind, RenderService

from . import pngs
from .helpers import draped, scene_with
from .service_helpers import Collector, count_frames


@pytest.fixture
def service(tmp_path):
    got = Collector()
    svc = RenderService(scene_with(), (96, 72), tmp_path / "captures", got.on_frame,
                        got.on_event)
    svc.got = got
    svc.start()
    yield svc
    svc.stop(timeout=10)


def test_paused_recording_holds_the_still_picture(service):
    service.submit(draped(scene_with()))
    service.got.frames.get(timeout=30)
    service.start_recording()  # no snapshot comes after this: the simulation is paused
    service.got.event(CaptureKind.VIDEO_STARTED)
    service.stop_recording()
    saved = service.got.event(CaptureKind.VIDEO_SAVED)
    assert count_frames(saved.path) >= 1


def test_recording_with_nothing_drawn_saves_no_file(service, tmp_path):
    service.start_recording()
    service.got.event(CaptureKind.VIDEO_STARTED)
    service.stop_recording()
    empty = service.got.event(CaptureKind.VIDEO_EMPTY)
    assert "no video saved" in empty.message
    assert not list((tmp_path / "captures").glob("*.mp4"))


def test_a_broken_texture_is_a_notice_and_captures_still_work(tmp_path):
    texture = tmp_path / "cut.png"
    rng = np.random.default_rng(2)
    texture.write_bytes(pngs.png(rng.integers(0, 256, (64, 64, 3)))[:600])  # truncated
    scene = scene_with(cloth_texture=str(texture))
    got = Collector()
    svc = RenderService(scene, (96, 72), tmp_path / "captures", got.on_frame, got.on_event)
    svc.start()
    try:
        svc.submit(draped(scene))
        got.frames.get(timeout=30)
        notice = got.event(CaptureKind.NOTICE)
        assert "cut.png" in notice.message and "drawn without it" in notice.message
        svc.screenshot()
        assert got.event(CaptureKind.SCREENSHOT).path.exists()
        svc.start_recording()
        got.event(CaptureKind.VIDEO_STARTED)
        svc.stop_recording()
        assert count_frames(got.event(CaptureKind.VIDEO_SAVED).path) >= 1
    finally:
        svc.stop(timeout=10)
