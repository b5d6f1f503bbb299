"""A frame flows one way: the scene reaches the renderer in the simulation's snapshots, not
also from the app beside them."""

from cloth_tui.scene import Scene

from .conftest import make_app, run, until

SIZE = (120, 40)


def test_an_appearance_edit_reaches_the_renderer_in_the_next_snapshot_alone(tmp_path):
    async def go():
        app = make_app(tmp_path, Scene())  # paused: the thread still publishes after commands
        async with app.run_test(size=SIZE) as pilot:
            await until(pilot, lambda: app.sim is not None and app.renderer.snapshot is not None,
                        what="the first snapshot")
            assert app.set_value("appearance.cloth_color", "#00ff00")
            await until(pilot, lambda: app.renderer.snapshot.scene.appearance.cloth_color
                        == "#00ff00", what="the edited scene in a snapshot")
            assert app.renderer.scene.appearance.cloth_color == "#00ff00"
            assert [c for c in app.renderer.calls if c[0] == "update_scene"] == []
    run(go())


def test_without_a_simulation_the_app_hands_the_renderer_the_scene(tmp_path):
    async def go():
        app = make_app(tmp_path, Scene())
        async with app.run_test(size=SIZE) as pilot:
            await until(pilot, lambda: app.sim is not None, what="the simulation")
            app.sim.stop()
            app.sim = None
            assert app.set_value("appearance.cloth_color", "#00ff00")
            assert app.renderer.calls[-1][0] == "update_scene"
            assert app.renderer.scene.appearance.cloth_color == "#00ff00"
    run(go())
