"""The app styles its ~700 panel widgets once at start-up, not again: Textual restyles a widget
and everything in it when one of its classes changes after it mounts, so the classes Textual
would set then (a folded group's, a plain Input's, the screen's width breakpoint) are given
at construction. Focusing the controls panel restyles the panel alone."""

from cloth_tui.tui.panels import Controls

from .conftest import SIZE, make_app, run, until

BIG = 50  # widgets: more than any one row, fewer than one group of rows


def restyles_of(app) -> list[int]:
    """The sizes (widgets) of the restyles the app's stylesheet makes from now on."""
    sizes: list[int] = []
    update_nodes = app.stylesheet.update_nodes

    def counted(nodes, animate=False):
        nodes = list(nodes)
        sizes.append(len(nodes))
        return update_nodes(nodes, animate=animate)

    app.stylesheet.update_nodes = counted
    return sizes


def test_start_up_restyles_the_panels_once_and_focus_on_the_panel_restyles_it_alone(tmp_path):
    async def go():
        app = make_app(tmp_path)
        sizes = restyles_of(app)
        async with app.run_test(size=SIZE) as pilot:
            await until(pilot, lambda: app.sim is not None, what="the simulation thread")
            for _ in range(3):
                await pilot.pause()
            controls = app.query_one(Controls)
            assert len(list(controls.walk_children())) > 300  # the panels are all there
            # Textual's own restyle of the first screen as it is shown, and no other
            big = [n for n in sizes if n > BIG]
            assert len(big) == 1, f"restyles at start-up of more than {BIG} widgets: {big}"

            sizes.clear()
            controls.focus()
            await pilot.pause()
            assert controls.has_focus
            assert sizes and max(sizes) <= 5, f"restyled on the panel's focus: {sizes}"
    run(go())
