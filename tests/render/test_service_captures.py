"""The render service's recordings when the simulation sends nothing new: a paused sheet is
recorded as its still picture; a recording with no picture at all leaves no file."""

import pytest

from cloth_tui.render.service import RenderService

from .helpers import draped, scene_with
from .test_capture import count_frames
from .test_service import Collector


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
    service.got.event("video_started")
    service.stop_recording()
    saved = service.got.event("video_saved")
    assert count_frames(saved.path) >= 1


def test_recording_with_nothing_drawn_saves_no_file(service, tmp_path):
    service.start_recording()
    service.got.event("video_started")
    service.stop_recording()
    empty = service.got.event("video_empty")
    assert "no video saved" in empty.message
    assert not list((tmp_path / "captures").glob("*.mp4"))
