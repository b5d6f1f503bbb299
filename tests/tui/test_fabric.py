"""The Fabric group: a user picks denim from the list or the palette, sees it named with its
values in units, edits one, and keeps it when another scene opens."""

from textual.widgets import Collapsible, Input, OptionList

from cloth_tui.scene import Scene
from cloth_tui.scene_files import load
from cloth_tui.tui.fabric_panel import FabricPanel
from cloth_tui.tui.panels import widget_id

from .conftest import SIZE, make_app, notifications, run, sim_scene, until


def _row_text(app, dotted: str) -> str:
    """What a row shows: its label, value and unit (or the note that replaces them)."""
    row = app.query_one("#" + widget_id(dotted) + "-row")
    parts = []
    for child in row.children:
        if not child.display:
            continue
        if isinstance(child, Input):
            parts.append(child.value)
        elif hasattr(child, "content"):
            parts.append(str(child.content))
    return " ".join(parts)


async def _open_fabric_group(app, pilot) -> None:
    group = app.query_one("#group-fabric", Collapsible)
    group.collapsed = False
    await pilot.pause(0.1)


def test_denim_from_the_list_shows_its_values_in_units_and_survives_the_sphere(tmp_path):
    async def go():
        app = make_app(tmp_path)
        async with app.run_test(size=SIZE) as pilot:
            await _open_fabric_group(app, pilot)
            presets = app.query_one("#fabric-presets", OptionList)
            presets.focus()
            await pilot.pause(0.1)
            assert app.focused is presets
            # the arrows move in the list (they would push the cloth elsewhere)
            start = presets.highlighted
            await pilot.press("down")
            assert presets.highlighted == (start or 0) + 1
            presets.highlighted = presets.get_option_index("denim")
            await pilot.press("enter")
            await until(pilot, lambda: app.scene.material is not None, what="denim on")
            assert app.scene.material.name == "denim"
            await until(pilot, lambda: sim_scene(app).material is not None, what="sim denim")
            assert "denim" in str(app.query_one("#fabric-title").content)
            assert _row_text(app, "fabric.weight") == "weight 324 g/m²"
            assert _row_text(app, "fabric.bending") == "bending 16.0491 µN·m"
            assert _row_text(app, "fabric.stretch_warp") == "stretch warp 410.704 N/m"
            assert _row_text(app, "fabric.damping") == "damping 0 1/s"
            # what the fabric replaces is shown as such, not as a live value
            assert _row_text(app, "cloth.mass") == "mass by the fabric"
            assert _row_text(app, "forces.gravity_strength") == "gravity strength 9.81 m/s²"
            assert any(m.startswith("Fabric: denim (11 oz twill denim, 324 g/m²")
                       for m in notifications(app))
            await until(pilot, lambda: app.readout.stats.material == "denim", what="status")
            app._refresh_status()
            assert "denim" in str(app.query_one("#cost-text").content)

            app.open_scene("sphere")
            await pilot.pause(0.1)
            assert app.scene.scene.object == "sphere" and app.scene.material.name == "denim"
            assert "Opened scene sphere; fabric denim kept (the scene names none)" \
                in notifications(app)
            assert "denim" in str(app.query_one("#fabric-title").content)
            assert _row_text(app, "fabric.weight") == "weight 324 g/m²"
            await until(pilot, lambda: sim_scene(app).scene.object == "sphere" and
                        sim_scene(app).material is not None, what="sim: sphere in denim")
    run(go())


def test_denim_from_the_palette(tmp_path):
    async def go():
        app = make_app(tmp_path)
        async with app.run_test(size=SIZE) as pilot:
            await pilot.press("ctrl+p")
            await pilot.pause(0.2)
            await pilot.press(*"denim")
            await pilot.pause(0.5)
            await pilot.press("enter")
            await until(pilot, lambda: app.scene.material is not None, what="denim on")
            assert app.scene.material.name == "denim"
            await pilot.pause(0.1)
            assert _row_text(app, "fabric.weight") == "weight 324 g/m²"
    run(go())


def test_a_fabric_value_is_edited_in_its_unit_and_bad_input_keeps_the_last_good(tmp_path):
    async def go():
        app = make_app(tmp_path, Scene().with_value("material.preset", "denim"))
        async with app.run_test(size=SIZE) as pilot:
            await _open_fabric_group(app, pilot)
            field = app.query_one("#" + widget_id("fabric.weight"), Input)
            field.focus()
            field.value = "250"
            await pilot.press("enter")
            await until(pilot, lambda: app.scene.material.material.areal_density == 0.25,
                        what="weight applied")
            assert app.scene.material.table == {"preset": "denim", "areal_density": 0.25}
            assert "weight set here" in str(app.query_one("#fabric-title").content)
            bending = app.query_one("#" + widget_id("fabric.bending"), Input)
            bending.focus()
            bending.value = "-3"
            await pilot.press("enter")
            await pilot.pause(0.1)
            assert bending.value == "16.0491"  # the last good value
            assert app.scene.material.material.bending == 64.196457e-6 / 4
            assert any("bending = -3 is not allowed" in m and "µN·m" in m
                       for m in notifications(app))
    run(go())


def test_a_scene_that_names_its_own_fabric_gets_it_and_defaults_restore_the_scenes(
        tmp_path, monkeypatch):
    own = tmp_path / "own.toml"
    own.write_text('[material]\npreset = "silk"\n')
    from cloth_tui.tui import fabric_actions
    monkeypatch.setattr(fabric_actions, "builtin_scenes", lambda: {"own": own})
    monkeypatch.setattr("cloth_tui.tui.app.load", lambda name: load(own))

    async def go():
        app = make_app(tmp_path, Scene().with_value("material.preset", "denim"))
        async with app.run_test(size=SIZE) as pilot:
            app.open_scene("own")
            await pilot.pause(0.1)
            assert app.scene.material.name == "silk"
            assert "Opened scene own; fabric: silk, the scene's own" in notifications(app)
            app.choose_fabric("leather")
            app.query_one("#defaults").press()
            await until(pilot, lambda: app.scene.material.name == "silk", what="defaults")
            assert any("fabric: silk, the scene's own" in m and "defaults" in m
                       for m in notifications(app))
            app.choose_fabric("original")
            await pilot.pause(0.1)
            assert app.scene.material is None
            assert app.query_one(FabricPanel).has_class("-original")
            assert _row_text(app, "cloth.mass") == "mass 0.2 kg"
    run(go())


def test_every_quantity_field_shows_its_unit_whole_and_help_tells_of_the_fabric(tmp_path):
    from cloth_tui.scene import key_spec, value_type
    from cloth_tui.tui.help import help_groups
    from cloth_tui.tui.panels import all_panel_keys

    async def go():
        app = make_app(tmp_path)
        async with app.run_test(size=SIZE) as pilot:
            for c in app.query(Collapsible):
                c.collapsed = False
            await pilot.pause(0.2)
            quantities = [k for k in all_panel_keys()
                          if value_type(key_spec(k)) == "float"
                          and not key_spec(k).metadata["choices"]]
            assert "forces.gravity_strength" in quantities
            for dotted in quantities:
                row = app.query_one("#" + widget_id(dotted) + "-row")
                unit = row.query_one(".setting-unit")
                text = str(unit.content)
                assert text, dotted
                assert unit.content_region.width >= len(text), f"{dotted}: {text} cut"
            assert _row_text(app, "behavior.damping") == "damping 0.03 /18 ms"
            assert _row_text(app, "forces.custom_strength") == "custom strength 10 m/s²"

            groups = help_groups(app)
            assert "Fabric" in groups
            assert any("g/m²" in what and "µN·m" in what for _, what in groups["Fabric"])
            assert any("fabric" in what for _, what in groups["Fields"])
    run(go())


def test_a_scene_whose_solver_takes_no_fabric_opens_without_it_and_says_why(tmp_path):
    async def go():
        app = make_app(tmp_path, Scene().with_value("material.preset", "denim"))
        async with app.run_test(size=SIZE) as pilot:
            app.open_scene("tear")  # pbd: no compliance for a fabric's constraints
            await pilot.pause(0.1)
            assert app.scene.behavior.solver == "pbd" and app.scene.material is None
            told = [m for m in notifications(app) if m.startswith("Opened scene tear")]
            assert told and "fabric denim not kept" in told[0] and "hpbd" in told[0]
            assert app.query_one(FabricPanel).has_class("-original")
            assert not app.choose_fabric("silk")  # refused, and told why
            assert app.scene.material is None
            assert any("needs behavior.solver" in m for m in notifications(app))
    run(go())


def test_the_status_line_names_the_fabric_without_an_error_tolerance_too():
    from cloth_tui.sim.run.run_stats import RunStats
    from cloth_tui.tui.status import Readout

    r = Readout()
    r.on_snapshot(1, RunStats(material="denim", frame_ms=3.0))
    _, cost = r.text(paused=False, recording=False, iterations=4, substeps=4)
    assert cost.startswith("denim · cost")


def test_a_measured_presets_stiffening_and_directions_are_told_and_typing_makes_it_linear(
        tmp_path):
    async def go():
        app = make_app(tmp_path, Scene().with_value("material.preset", "denim"))
        async with app.run_test(size=SIZE) as pilot:
            note = app.query_one("#fabric-measured")
            assert note.display
            text = str(note.content)
            assert "stiffens with strain (warp 411 → " in text and "0°/45°/90°" in text
            field = app.query_one("#" + widget_id("fabric.stretch_warp"), Input)
            field.focus()
            field.value = "300"
            await pilot.press("enter")
            await until(pilot, lambda: app.scene.material.material.stretch_curves is None,
                        what="a typed stretch: linear")
            assert app.scene.material.table["stretch"] == [300.0, 2027.77258]
            text = str(app.query_one("#fabric-measured").content)
            assert "stiffens" not in text and "0°/45°/90°" in text
            app.choose_fabric("cotton")  # an estimate: linear, nothing more to tell
            await pilot.pause(0.1)
            assert not app.query_one("#fabric-measured").display
    run(go())


def test_the_tear_length_is_shown_in_mm_and_edited_like_the_other_values(tmp_path):
    async def go():
        app = make_app(tmp_path, Scene().with_value("material.preset", "denim"))
        async with app.run_test(size=SIZE) as pilot:
            await _open_fabric_group(app, pilot)
            assert _row_text(app, "fabric.tear_length") == "tear length 5 mm"  # the default
            field = app.query_one("#" + widget_id("fabric.tear_length"), Input)
            field.focus()
            field.value = "2.5"
            await pilot.press("enter")
            await until(pilot, lambda: app.scene.material.material.tear_length == 0.0025,
                        what="tear length applied")
            assert app.scene.material.table == {"preset": "denim", "tear_length": 0.0025}
            await until(pilot, lambda: sim_scene(app).material.material.tear_length == 0.0025,
                        what="the simulation's fabric")
            assert "tear length set here" in str(app.query_one("#fabric-title").content)
            field.focus()
            field.value = "2000"  # 2 m: beyond the key's 1 m
            await pilot.press("enter")
            await pilot.pause(0.1)
            assert field.value == "2.5"  # the last good value
            assert app.scene.material.material.tear_length == 0.0025
            assert any("tear length = 2000 is not allowed" in m and "mm" in m
                       for m in notifications(app))
    run(go())
