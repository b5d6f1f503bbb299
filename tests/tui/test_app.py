"""Pilot tests: each key and each kind of panel control changes the simulation or the view.

Starting the app costs ~2 s (about 300 widgets), so related checks share one session."""

import numpy as np
import pytest
from textual.widgets import Collapsible, Input, Select, Switch

from cloth_tui.scene import Scene, all_keys
from cloth_tui.scene_files import load
from cloth_tui.tui.app import run_app
from cloth_tui.tui.bindings import BUMP_M
from cloth_tui.tui.panels import all_panel_keys, widget_id
from cloth_tui.tui.preview import SCALE

from .conftest import SIZE, make_app, notifications, run, sim_scene, until
from .fakes import CaptureEvent, CaptureKind


async def _type_into(pilot, app, dotted: str, text: str) -> Input:
    field = app.query_one("#" + widget_id(dotted), Input)
    field.focus()
    field.value = text
    await pilot.press("enter")
    await pilot.pause()
    return field


def test_panel_controls_change_the_scene(tmp_path):
    assert sorted(all_panel_keys()) == sorted(all_keys())

    async def go():
        app = make_app(tmp_path)
        async with app.run_test(size=SIZE) as pilot:
            # one control per scene key, in four groups, and the Fabric group
            for dotted in all_keys():
                assert app.query_one("#" + widget_id(dotted)) is not None
            assert [c.title for c in app.query(Collapsible)
                    if (c.id or "").startswith("group-")] \
                == ["Fabric", "Forces", "Scene", "Behavior", "Appearance"]
            assert app.sim.paused  # commands still run between frames while paused

            # Switch → app scene, sim scene and renderer scene (in the sim's next snapshot)
            app.query_one("#" + widget_id("forces.wind"), Switch).value = True
            await until(pilot, lambda: sim_scene(app).forces.wind, what="sim scene")
            await until(pilot, lambda: app.renderer.scene.forces.wind, what="renderer scene")
            assert app.scene.forces.wind

            # Select
            app.query_one("#" + widget_id("behavior.solver"), Select).value = "xpbd"
            await until(pilot, lambda: sim_scene(app).behavior.solver == "xpbd")

            # invalid inputs are refused with a notification; the last good value returns
            field = await _type_into(pilot, app, "forces.gravity_strength", "-3")
            assert app.scene.forces.gravity_strength == 9.81 and field.value == "9.81"
            assert app.focused is field  # refused: still there for another try
            assert any("forces.gravity_strength" in m for m in notifications(app))
            field = await _type_into(pilot, app, "appearance.cloth_color", "red")
            assert field.value == "#aa2929" and app.scene.appearance.cloth_color == "#aa2929"

            # numbers, vectors, colours apply; resolution rebuilds the sheet
            field = await _type_into(pilot, app, "cloth.resolution", "10")
            # accepted with Enter: on to the next field
            assert app.focused is app.query_one("#" + widget_id("appearance.wireframe"))
            await until(pilot, lambda: app.sim.sim.model.nx == app.sim.sim.model.nz == 10,
                        what="rebuilt model")
            await _type_into(pilot, app, "forces.wind_direction", "[1, 0, 0]")
            assert app.scene.forces.wind_direction == [1.0, 0.0, 0.0]
            await _type_into(pilot, app, "appearance.fog_color", "#000000")
            await until(pilot, lambda: app.renderer.scene.appearance.fog_color == "#000000",
                        what="the fog colour in the renderer")

            # leaving a field (blur) validates too
            field = app.query_one("#" + widget_id("behavior.iterations"), Input)
            field.focus()
            await pilot.pause(0.05)
            field.value = "9"
            app.set_focus(None)
            await until(pilot, lambda: sim_scene(app).behavior.iterations == 9)

            # keys typed into a field stay in the field; escape gives them back to the app
            field = app.query_one("#" + widget_id("appearance.cloth_texture"), Input)
            field.focus()
            await pilot.pause(0.05)
            field.value = ""
            await pilot.press("w", "a", "q")
            assert field.value == "waq"
            assert app.scene.appearance.wireframe is False and app.is_running
            await pilot.press("escape", "w")
            assert app.scene.appearance.wireframe is True
    run(go())


def test_view_keys_save_and_hide(tmp_path):
    async def go():
        app = make_app(tmp_path, Scene().with_value("forces.wind", True))
        async with app.run_test(size=SIZE) as pilot:
            await pilot.press("w")
            assert app.scene.appearance.wireframe is True
            assert app.query_one("#" + widget_id("appearance.wireframe"), Switch).value is True
            await until(pilot, lambda: app.renderer.scene.appearance.wireframe)
            await pilot.press("a")
            assert app.scene.appearance.auto_rotate is True

            await pilot.press("left_square_bracket", "full_stop", "plus", "minus", "o")
            kinds = [c[0] for c in app.renderer.calls]
            assert kinds.count("orbit") == 2 and kinds.count("zoom") == 2
            assert "reset_camera" in kinds and "resize" in kinds

            await pilot.press("s")
            saved = list((tmp_path / "caps").glob("scene-*.toml"))
            assert len(saved) == 1 and load(saved[0]) == app.scene
            assert any(str(saved[0]) in m for m in notifications(app))

            await pilot.press("c")
            assert not app.controls.display
            await pilot.press("c")
            assert app.controls.display
            await pilot.click("#hide")  # the original's "Close controls" button
            assert not app.controls.display
    run(go())


def test_pause_restart_and_buttons(tmp_path):
    async def go():
        app = make_app(tmp_path, Scene().with_value("behavior.iterations", 7),
                       start_paused=False)
        async with app.run_test(size=SIZE) as pilot:
            await until(pilot, lambda: app.sim.latest.frame > 20, what="frames")
            await pilot.press("space")
            assert app.sim.paused
            await pilot.pause(0.1)
            f = app.sim.latest.frame
            await pilot.pause(0.2)
            assert app.sim.latest.frame == f
            await pilot.press("r")
            await until(pilot, lambda: app.sim.latest.frame == 0, what="reset")
            await pilot.press("space")
            await until(pilot, lambda: app.sim.latest.frame > 5, what="running again")

            await pilot.click("#defaults")
            assert app.scene == Scene()
            await until(pilot, lambda: sim_scene(app).behavior.iterations == 4)
            await until(pilot, lambda: app.sim.latest.frame > 5)
            # the clicked button has focus (space would press it): escape, then space pauses
            await pilot.press("escape")
            await until(pilot, lambda: app.focused is None, what="focus left")
            await pilot.press("space")  # paused: the restarted sheet stays at frame 0
            await pilot.click("#restart")
            await until(pilot, lambda: app.sim.latest.frame == 0, what="restart")
    run(go())


def test_bumps_crosshair_drag_and_preview(tmp_path):
    async def go():
        app = make_app(tmp_path)
        async with app.run_test(size=SIZE) as pilot:
            await until(pilot, lambda: app.preview.frames_shown > 0)
            await pilot.pause(0.1)
            preview = app.preview

            # the preview is half-blocks of an image of the requested size
            strip = preview.render_line(preview.size.height // 2)
            text = "".join(seg.text for seg in strip)
            assert set(text) <= {"▀", "╋"} and len(text) == preview.size.width
            w, h = app.renderer.size
            assert (w, h) == (SCALE * preview.size.width, SCALE * 2 * preview.size.height)
            assert np.asarray(app.renderer.render()).shape == (h, w, 3)

            # without a mouse, keys act at the crosshair, which h j k l move
            assert preview.pointer is None
            start = preview.crosshair
            await pilot.press("l", "l", "k")
            u, v = preview.crosshair
            assert u > start[0] and v < start[1]
            await pilot.press("h", "h", "j")
            target = app.renderer.pick(*preview.crosshair)
            x0 = app.sim.latest.positions[target][0]
            await pilot.press("right")
            await until(pilot, lambda: app.sim.latest.positions[target][0] > x0)

            # with the mouse over the preview, arrows bump the particle under it
            await pilot.hover("#preview", offset=(preview.size.width // 2, 10))
            target = app.renderer.pick(*preview.target)
            before = app.sim.latest.positions[target].copy()
            await pilot.press("up")
            await until(pilot, lambda: app.sim.latest.positions[target][1] > before[1])
            assert app.sim.latest.positions[target][1] == pytest.approx(before[1] + BUMP_M)
            await pilot.press("pageup")
            await until(pilot, lambda: app.sim.latest.positions[target][2] > before[2])

            # dragging grabs a particle and pulls it along
            wd = preview.size.width
            await pilot.mouse_down("#preview", offset=(wd // 2, 14))
            grabbed = app._grabbed
            assert grabbed is not None
            y0 = app.sim.latest.positions[grabbed][1]
            await pilot.hover("#preview", offset=(wd // 2, 10))
            await until(pilot, lambda: app.sim.latest.positions[grabbed][1] > y0 + 0.01)
            # through the camera (the renderer's view plane), not a fixed scale
            drags = [c for c in app.renderer.calls if c[0] == "screen_delta_to_world"]
            assert drags and drags[-1][1] == grabbed and drags[-1][3] < 0
            await pilot.mouse_up("#preview", offset=(wd // 2, 10))
            assert app._grabbed is None
    run(go())


def test_captures_and_failures_are_reported(tmp_path):
    async def go():
        app = make_app(tmp_path)
        async with app.run_test(size=SIZE) as pilot:
            await pilot.press("i")
            await until(pilot, lambda: any("Screenshot saved" in m for m in notifications(app)))
            await pilot.press("v")
            assert app.renderer.recording
            await pilot.pause(0.3)
            assert "REC" in str(app.query_one("#status-text").render())
            assert "ms/step" in str(app.query_one("#cost-text").render())
            await pilot.press("v")
            assert not app.renderer.recording
            await until(pilot, lambda: any("Video saved" in m for m in notifications(app)))
            app.renderer.on_event(CaptureEvent(CaptureKind.ERROR, None, "disk full"))
            await until(pilot, lambda: "disk full" in notifications(app))
            app.sim.error = RuntimeError("boom")
            app.sim.on_died(app.sim.error)  # as the thread tells of its end
            await until(pilot, lambda: any("boom" in m for m in notifications(app)))
            assert app.is_running
            dead = app.sim
            await pilot.press("r")  # a new simulation thread replaces the dead one
            assert app.sim is not dead and app.sim.error is None
            assert not dead._thread.is_alive()
            await until(pilot, lambda: app.sim.latest.frame > 2, what="new sim running")
    run(go())


def test_open_builtin_scene_from_command_palette(tmp_path):
    async def go():
        app = make_app(tmp_path, Scene().with_value("forces.wind", True))
        async with app.run_test(size=SIZE) as pilot:
            await pilot.press("ctrl+p")
            await pilot.pause(0.2)
            await pilot.press(*"default")
            await pilot.pause(0.5)
            await pilot.press("enter")
            await until(pilot, lambda: not app.scene.forces.wind, what="scene opened")
            assert app.scene == load("default")
    run(go())


def test_q_quits_finishing_video_and_stopping_threads(tmp_path):
    async def go():
        app = make_app(tmp_path)
        async with app.run_test(size=SIZE) as pilot:
            await pilot.press("v")
            await pilot.press("q")
        assert app.return_code == 0
        assert not app.sim._thread.is_alive()
        assert app.renderer.stopped and not app.renderer.recording
    run(go())


def test_run_app_refuses_unusable_captures_dir(tmp_path, capsys):
    blocker = tmp_path / "file"
    blocker.write_text("x")
    assert run_app(Scene(), blocker / "caps") == 2
    err = capsys.readouterr().err
    assert "captures" in err and len(err.strip().splitlines()) == 1


def test_run_app_shortens_the_gil_switch_interval_while_it_runs(tmp_path):
    # The simulation thread must get the GIL back quickly between its compiled calls while
    # the UI thread runs Python; the process's own interval comes back afterwards.
    import sys

    from cloth_tui.tui import process

    seen = []

    class Probe:
        crash, return_code = None, 0

        def __init__(self, scene, captures_dir, **kwargs):
            pass

        def run(self):
            seen.append(sys.getswitchinterval())

    before = sys.getswitchinterval()
    assert run_app(Scene(), tmp_path / "caps", app_class=Probe) == 0
    # Python keeps the interval in whole microseconds (0.0001 reads back as 9.999…e-05)
    assert seen == [pytest.approx(process.GIL_SWITCH_INTERVAL_S, abs=1e-6)]
    assert before > seen[0]
    assert sys.getswitchinterval() == before


def test_t_key_keeps_the_physics_on_one_thread(tmp_path):
    from cloth_tui.sim import threads

    async def go():
        app = make_app(tmp_path)
        async with app.run_test(size=SIZE) as pilot:
            try:
                await pilot.press("t")
                assert threads.single_thread_forced()
                assert "Physics on one thread" in notifications(app)
                await pilot.press("t")
                assert not threads.single_thread_forced()
            finally:
                threads.force_single_thread(False)
    run(go())


def test_the_palette_screenshot_is_the_apps_own(tmp_path):
    """Not Textual's SVG of the terminal beside the app's `i`: the one entry takes the PNG."""
    async def go():
        app = make_app(tmp_path)
        async with app.run_test(size=SIZE):
            shots = [c for c in app.get_system_commands(app.screen) if "creenshot" in c.title]
            assert len(shots) == 1 and "PNG" in shots[0].help and "SVG" not in shots[0].help
            shots[0].callback()
            assert any(c[0] == "screenshot" for c in app.renderer.calls)
    run(go())
