"""Files the app writes: scenes saved within one second each get their own file."""

from .conftest import SIZE, make_app, notifications, run, until


def test_scenes_saved_within_a_second_get_their_own_files(tmp_path):
    async def go():
        app = make_app(tmp_path)
        async with app.run_test(size=SIZE) as pilot:
            for _ in range(5):
                await pilot.press("s")
            await until(pilot, lambda: sum("Scene saved" in m for m in notifications(app)) == 5)
        names = sorted(p.name for p in (tmp_path / "caps").glob("scene-*.toml"))
        assert len(names) == 5, names
    run(go())


def test_scene_save_on_a_full_disk_says_so_and_leaves_nothing(tmp_path, monkeypatch):
    import errno
    import os

    def full(*args, **kwargs):
        raise OSError(errno.ENOSPC, os.strerror(errno.ENOSPC))

    async def go():
        app = make_app(tmp_path)
        async with app.run_test(size=SIZE) as pilot:
            (tmp_path / "caps").mkdir(exist_ok=True)
            monkeypatch.setattr(os, "replace", full)
            await pilot.press("s")
            await until(pilot, lambda: any("No space left on device" in m
                                           for m in notifications(app)))
            monkeypatch.undo()
        assert [p.name for p in (tmp_path / "caps").iterdir()] == []
    run(go())


def test_texture_notice_and_empty_recording_are_shown(tmp_path):
    from .fakes import CaptureEvent, CaptureKind

    async def go():
        app = make_app(tmp_path)
        async with app.run_test(size=SIZE) as pilot:
            app.renderer._event(CaptureEvent(CaptureKind.NOTICE, None,
                                             "texture cut.png: truncated; drawn without it"))
            app.renderer._event(CaptureEvent(CaptureKind.VIDEO_EMPTY, None, "nothing was drawn"))
            await until(pilot, lambda: len(notifications(app)) >= 2)
            shown = notifications(app)
            assert any("cut.png" in m and "drawn without it" in m for m in shown)
            assert any(m.startswith("Nothing recorded") for m in shown)
            assert not any("Video saved" in m for m in shown)
    run(go())
