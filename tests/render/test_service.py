import time

import numpy as np
import pytest

from cloth_tui.render.service import CaptureKind, RenderService

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


def test_renders_on_its_own_thread_and_saves_screenshots(service):
    got = service.got
    snap = draped(scene_with())
    service.submit(snap)
    frame = got.frames.get(timeout=30)
    assert frame.image.shape == (72, 96, 3) and frame.frame == snap.frame
    assert frame.render_ms > 0 and got.threads == {"cloth-render"}
    service.screenshot()
    shot = got.event(CaptureKind.SCREENSHOT)
    assert shot.path.exists() and shot.path.suffix == ".png"
    assert (shot.path.parent / "preview.png").exists()
    # Drawn again at 720 px, framed like the 96×72 preview; the preview keeps its size.
    import imageio.v3 as iio
    assert iio.imread(shot.path).shape == (720, 960, 3)
    service.submit(draped(scene_with(), frame=5))
    assert got.frames.get(timeout=10).image.shape == (72, 96, 3)


def test_camera_and_size_commands_redraw(service):
    got = service.got
    service.submit(draped(scene_with()))
    first = got.frames.get(timeout=30).image
    service.orbit(30, 0)
    assert not np.array_equal(got.frames.get(timeout=10).image, first)
    service.resize(51, 33)
    assert got.frames.get(timeout=10).image.shape == (33, 51, 3)


def test_pick_from_the_ui_thread(service):
    service.submit(draped(scene_with(), sag=0.02))
    service.got.frames.get(timeout=30)
    snap = draped(scene_with(), sag=0.02)
    assert service.pick(0.5, 0.02) is None  # sky
    assert service.pick(0.5, 0.3) in range(snap.model.num_particles)


def test_screen_delta_follows_an_orbited_camera(service):
    """A drag's world motion lies in the view plane at the particle's depth and moves the
    particle's picture by exactly (du, dv), whatever the orbit."""
    import math
    snap = draped(scene_with(), sag=0.1)
    k = snap.model.nx * (snap.model.nz // 2) + 3
    assert service.screen_delta_to_world(k, 0.1, 0.0) is None  # nothing drawn yet
    service.orbit(70, 25)
    service.submit(snap)
    service.got.frames.get(timeout=30)
    r = service._renderer
    az, el = math.radians(r.camera.azimuth), math.radians(r.camera.elevation)
    assert abs(r.camera.azimuth - 104) < 1e-9  # home 34° + 70°: seen from the other side
    view = -np.array([math.cos(el) * math.sin(az), math.sin(el), math.cos(el) * math.cos(az)])
    m, positions = r._pick_state

    def project(x):
        h = m @ np.r_[x, 1.0]
        return np.array([(h[0] / h[3] + 1) / 2, (1 - h[1] / h[3]) / 2, h[3]])

    p = positions[k]
    for du, dv in ((0.1, 0.0), (0.0, -0.05), (-0.03, 0.07)):
        d = np.array(service.screen_delta_to_world(k, du, dv))
        assert np.linalg.norm(d) > 1e-3
        assert abs(d @ view) < 1e-9 * max(1.0, np.linalg.norm(d))  # perpendicular
        before, after = project(p), project(p + d)
        assert after[:2] == pytest.approx(before[:2] + (du, dv), abs=1e-9)
        assert after[2] == pytest.approx(before[2])  # same depth
    # screen right is the camera's right: up × back, not world +x, after the orbit
    right = np.cross(view, [0.0, 1.0, 0.0])
    right /= np.linalg.norm(right)
    d = np.array(service.screen_delta_to_world(k, 0.1, 0.0))
    assert d @ right > 0.9 * np.linalg.norm(d) and d[0] < 0  # azimuth 104°: +x is leftish
    assert service.screen_delta_to_world(snap.model.num_particles, 0.1, 0.0) is None
    assert service.screen_delta_to_world(k, math.nan, 0.0) is None


def test_recording_makes_a_video(service):
    got = service.got
    service.submit(draped(scene_with()))
    got.frames.get(timeout=30)
    service.toggle_recording()
    assert service.recording
    started = got.event(CaptureKind.VIDEO_STARTED)
    t0 = time.monotonic()
    for k in range(8):
        service.submit(draped(scene_with(), sag=0.02 * k, frame=k + 2))
        got.frames.get(timeout=10)
        time.sleep(0.05)
    elapsed = time.monotonic() - t0
    service.stop_recording()
    assert not service.recording
    saved = got.event(CaptureKind.VIDEO_SAVED)
    # Real time at 30 fps: frames are repeated or skipped to match the wall clock.
    assert saved.path == started.path
    import imageio.v3 as iio
    assert iio.imread(saved.path, index=0).shape == (480, 640, 3)  # VIDEO_HEIGHT, 4:3 preview
    assert 0.5 * elapsed * 30 <= count_frames(saved.path) <= elapsed * 30 + 6


def test_auto_rotate_keeps_turning_while_paused(service):
    service.submit(draped(scene_with(auto_rotate=True)))
    first = service.got.frames.get(timeout=30)
    later = service.got.frames.get(timeout=5)  # no new snapshot, yet a new picture
    assert later.frame == first.frame
    assert not np.array_equal(later.image, first.image)


def test_stop_finishes_a_running_video(tmp_path):
    got = Collector()
    svc = RenderService(scene_with(), (64, 48), tmp_path, got.on_frame, got.on_event,
                        preview_file=False).start()
    svc.start_recording()
    for k in range(4):
        svc.submit(draped(scene_with(), sag=0.05 * k, frame=k))
        got.frames.get(timeout=30)
    svc.stop(timeout=10)
    saved = got.event(CaptureKind.VIDEO_SAVED)
    assert count_frames(saved.path) >= 1 and not (tmp_path / "preview.png").exists()


def test_unwritable_captures_folder_reports_an_error(tmp_path):
    blocker = tmp_path / "file"
    blocker.write_text("x")
    got = Collector()
    svc = RenderService(scene_with(), (32, 24), blocker / "captures", got.on_frame,
                        got.on_event).start()
    try:
        assert got.events.get(timeout=30).kind == CaptureKind.ERROR  # preview file disabled
        svc.submit(draped(scene_with()))
        got.frames.get(timeout=10)  # still renders
        svc.screenshot()
        error = got.events.get(timeout=10)
        assert error.kind == CaptureKind.ERROR and "\n" not in error.message
        svc.start_recording()
        assert got.events.get(timeout=10).kind == CaptureKind.ERROR
        assert not svc.recording
    finally:
        svc.stop(timeout=10)
