"""`cloth-tui BAKE.usdc`: the app plays a bake with a timeline (Pilot, fake renderer)."""

import numpy as np
import pytest

from cloth_tui.cli import main

from .conftest import SIZE, notifications, run, until
from .fakes import FakeRenderService

pytest.importorskip("pxr")

from cloth_tui.io.usd_read import UsdBake  # noqa: E402
from cloth_tui.tui.replay_app import ReplayApp  # noqa: E402
from cloth_tui.tui.timeline import Timeline  # noqa: E402

FRAMES = 16


@pytest.fixture(scope="module")
def bake_path(tmp_path_factory):
    out = tmp_path_factory.mktemp("bake") / "drop.usdc"
    assert main(["bake", "default", "-o", str(out), "--frames", str(FRAMES),
                 "--set", "cloth.resolution=6", "--set", "behavior.frame_rate=30"]) == 0
    return out


def make_replay(tmp_path, bake_path, *, playing=False) -> ReplayApp:
    bake = UsdBake(bake_path)
    return ReplayApp(bake.scene, tmp_path / "caps", bake=bake,
                     renderer_factory=FakeRenderService, start_paused=not playing)


def shown(app: ReplayApp) -> int:
    """The bake frame the renderer was last given."""
    return app.renderer.snapshot.frame


def status(app: ReplayApp) -> str:
    return str(app.query_one("#status-text").render())


def test_play_advances_and_pause_holds(tmp_path, bake_path):
    async def go():
        app = make_replay(tmp_path, bake_path)
        async with app.run_test(size=SIZE) as pilot:
            await pilot.pause(0.2)
            assert shown(app) == 1 and not app.player.playing  # paused on the first frame
            assert "frame 1/16" in status(app) and "bake 30 fps" in status(app)
            await pilot.press("space")
            await until(pilot, lambda: shown(app) >= 4, what="playback to advance")
            assert app.player.playing and "playing" in status(app)
            await pilot.press("space")
            held = shown(app)
            await pilot.pause(0.3)  # 9 frames' time at 30 fps
            assert shown(app) == held and app.player.index == held - 1
            assert "paused" in status(app) and f"frame {held}/16" in status(app)
    run(go())


def test_arrows_step_and_home_end_jump(tmp_path, bake_path):
    async def go():
        app = make_replay(tmp_path, bake_path)
        async with app.run_test(size=SIZE) as pilot:
            await pilot.press("right", "right", "right")
            assert shown(app) == 4
            await pilot.press("left")
            assert shown(app) == 3
            await pilot.press("end")
            assert shown(app) == FRAMES and "frame 16/16" in status(app)
            await pilot.press("right")  # the last frame stays the last
            assert shown(app) == FRAMES
            await pilot.press("home")
            assert shown(app) == 1
            await pilot.press("shift+right")
            assert shown(app) == 11
    run(go())


def test_a_click_on_the_timeline_scrubs_and_the_preview_shows_that_frame(tmp_path, bake_path):
    async def go():
        app = make_replay(tmp_path, bake_path)
        bake = UsdBake(bake_path)
        async with app.run_test(size=SIZE) as pilot:
            timeline = app.query_one(Timeline)
            width = timeline.size.width
            target = 10  # index 10: bake frame 11
            x = round(target / (FRAMES - 1) * (width - 1))
            assert timeline.index_at(x) == target
            await pilot.click(Timeline, offset=(x, 0))
            await until(pilot, lambda: shown(app) == target + 1, what="the scrubbed frame")
            assert timeline.position == target
            np.testing.assert_array_equal(app.renderer.snapshot.positions,
                                          bake.positions(target + 1))
            # what the preview shows is the picture of those positions, not of frame 1
            await until(pilot, lambda: app._frames.newest is not None
                        and app._frames.newest.frame == target + 1, what="the frame drawn")
            assert np.array_equal(app._frames.newest.image, app.renderer.render())
            assert not np.allclose(bake.positions(1), bake.positions(target + 1))
            # a drag to the start scrubs back
            await pilot.mouse_down(Timeline, offset=(x, 0))
            await pilot.hover(Timeline, offset=(0, 0))
            await pilot.mouse_up(Timeline, offset=(0, 0))
            assert shown(app) == 1
    run(go())


def test_keys_still_step_after_a_click_on_the_preview(tmp_path, bake_path):
    async def go():
        app = make_replay(tmp_path, bake_path)
        async with app.run_test(size=SIZE) as pilot:
            await pilot.click("#preview", offset=(10, 5))
            await pilot.press("right")
            assert shown(app) == 2
    run(go())


def test_camera_appearance_and_capture_keys_reach_the_renderer(tmp_path, bake_path):
    async def go():
        app = make_replay(tmp_path, bake_path)
        async with app.run_test(size=SIZE) as pilot:
            await pilot.press("right_square_bracket", "plus", "o", "w", "i", "v")
            names = [c[0] for c in app.renderer.calls]
            for call in ("orbit", "zoom", "reset_camera", "update_scene", "screenshot"):
                assert call in names
            assert app.scene.appearance.wireframe != UsdBake(bake_path).scene.appearance.wireframe
            assert app.renderer.recording and "● REC" in status(app)
            await pilot.press("v")
            await until(pilot, lambda: any(m.startswith("Video saved") for m in notifications(app)),
                        what="'Video saved' notice")
    run(go())


def test_the_app_refuses_a_broken_bake_and_physics_settings_exit_2(tmp_path, bake_path,
                                                                   capsys):
    broken = tmp_path / "broken.usdc"
    broken.write_bytes(b"not usd")
    for argv in ([str(broken)], [str(tmp_path / "missing.usda")],
                 [str(bake_path), "--set", "behavior.substeps=3"]):
        assert main([*argv, "--captures", str(tmp_path / "caps")]) == 2
        err = capsys.readouterr().err
        assert err.count("\n") == 1 and "Traceback" not in err


def test_without_usd_core_the_app_says_which_extra_exit_2(tmp_path, bake_path, capsys,
                                                          monkeypatch):
    import cloth_tui.io.usd_read as usd_read
    monkeypatch.setattr(usd_read, "missing_usd_message",
                        lambda: "USD needs Pixar's usd-core: pip install 'cloth-tui[usd]'")
    assert main([str(bake_path), "--captures", str(tmp_path / "caps")]) == 2
    err = capsys.readouterr().err
    assert err.count("\n") == 1 and "cloth-tui[usd]" in err


def test_the_command_line_opens_a_bake_in_the_replay_app(tmp_path, bake_path, monkeypatch):
    opened = []
    monkeypatch.setattr(ReplayApp, "run", lambda self: opened.append(self))
    assert main([str(bake_path), "--set", "appearance.wireframe=false",
                 "--captures", str(tmp_path / "caps")]) == 0
    (app,) = opened
    assert isinstance(app, ReplayApp) and app.player.count == FRAMES
    assert app.scene.appearance.wireframe is False and app.start_paused is False


def test_the_replay_draws_no_crosshair(tmp_path, bake_path):
    from cloth_tui.tui.preview import CROSSHAIR

    async def go():
        app = make_replay(tmp_path, bake_path)
        async with app.run_test(size=SIZE) as pilot:
            await until(pilot, lambda: app.preview.frames_shown > 1, what="frames")
            lines = [app.preview.render_line(y).text for y in range(app.preview.size.height)]
            assert not any(CROSSHAIR in line for line in lines)
    run(go())
