"""[[pins]] tables: what they accept, what they refuse (one line naming the key), and that
they round-trip through a saved scene file and through `--set pins=[...]`; any array of
tables gives a scene and a model that hold what the tables say, or one SceneError."""

import numpy as np
import pytest
from hypothesis import HealthCheck, given, settings
from hypothesis import strategies as st

from cloth_tui import scene_files as sf
from cloth_tui.pin_groups import PinGroup, span
from cloth_tui.scene import Scene, SceneError
from cloth_tui.sim.model import build_model
from cloth_tui.sim.effects.pins import group_particles

GROUPS = ('pins=[{rows=[0,0], cols=[0,-1], offset=[0.1,0.05,0]}, '
          '{at=[[3,4],[-1,-1]], stiffness=0.8}, {cols=[2,2], keys=[[0,0,0,0],[1.5,0,0.2,0]]}]')


def with_groups(*extra):
    return sf.apply_overrides(Scene(), ["cloth.pinned=none", GROUPS, *extra])


def test_set_reads_the_whole_array_of_tables():
    s = with_groups()
    assert s.pins == [PinGroup(rows=[0, 0], cols=[0, -1], offset=[0.1, 0.05, 0.0]),
                      PinGroup(at=[[3, 4], [-1, -1]], stiffness=0.8),
                      PinGroup(cols=[2, 2], keys=[[0.0, 0.0, 0.0, 0.0], [1.5, 0.0, 0.2, 0.0]])]
    assert sf.apply_overrides(s, ["pins=[]"]).pins == []


def test_groups_round_trip_through_a_saved_file(tmp_path):
    s = with_groups()
    path = sf.save(s, tmp_path / "pinned.toml")
    text = path.read_text()
    assert text.count("[[pins]]") == 3
    assert "rows = [0, 0]" in text and "stiffness = 0.8" in text
    assert "offset" not in text.split("[[pins]]")[3]  # defaults are left out
    assert sf.load(path) == s


def test_keys_interpolate_linearly_and_hold_at_both_ends():
    g = PinGroup(at=[[0, 0]], keys=[[1.0, 0, 0, 0], [3.0, 0.2, -0.4, 0]])
    assert g.offset_at(0.0) == (0, 0, 0)
    assert g.offset_at(2.0) == pytest.approx((0.1, -0.2, 0))
    assert g.offset_at(2.5) == pytest.approx((0.15, -0.3, 0))
    assert g.offset_at(9.0) == (0.2, -0.4, 0)


def test_ranges_count_from_the_end_as_in_python():
    assert span([0, -1], 5, "r", "rows") == range(0, 5)
    assert span([-2, -1], 5, "r", "rows") == range(3, 5)
    assert span([], 5, "r", "rows") == range(0, 5)


@pytest.mark.parametrize("value, words", [
    ("[{rows=[0,26]}]", "pins[0].rows = [0, 26] is outside the sheet: it has 26 rows"),
    ("[{cols=[-27,0]}]", "pins[0].cols = [-27, 0] is outside the sheet"),
    ("[{at=[[0,26]]}]", "pins[0].at: [0, 26] is outside the sheet of 26 rows × 26 columns"),
    ("[{rows=[4,2]}]", "pins[0].rows = [4, 2] is empty"),
    ("[{}]", "pins[0] holds no particles"),
    ("[{offset=[0,0.1,0]}]", "pins[0] holds no particles"),
    ("[{at=[[0,0]], rows=[0,0]}]", "rows/cols or with at, not both"),
    ("[{at=[[0,0]], keys=[[0,0,0,0],[0,0,0.1,0]]}]", "key times must increase (0 s is "
                                                      "followed by 0 s)"),
    ("[{at=[[0,0]], keys=[[2,0,0,0],[1,0,0,0]]}]", "key times must increase"),
    ("[{at=[[0,0]], keys=[]}]", "give at least one"),
    ("[{at=[[0,0]], keys=[[0,0,0,0]], offset=[0,0,0]}]", "leave out offset"),
    ("[{at=[[0,0]], offset=[nan,0,0]}]", "not a finite number"),
    ("[{at=[[0,0]], keys=[[inf,0,0,0]]}]", "not a finite number"),
    ("[{at=[[0,0]], stiffness=0}]", "0 < value ≤ 1"),
    ("[{at=[[0,0]], stiffness=1.5}]", "0 < value ≤ 1"),
    ("[{at=[[0,0.5]]}]", "integers"),
    ("[{rows=[0]}]", "[first, last]"),
    ("[{at=[[0,0]], weight=1}]", "unknown key pins[0].weight"),
    ("[1]", "pins[0] must be a table"),
    ("{rows=[0,0]}", "pins must be an array of tables"),
])
def test_bad_groups_are_refused_with_one_line(value, words):
    with pytest.raises(SceneError) as e:
        sf.apply_overrides(Scene(), ["cloth.pinned=none", f"pins={value}"])
    assert words in str(e.value) and "\n" not in str(e.value)


def test_a_smaller_sheet_is_refused_when_a_group_falls_off_it():
    s = with_groups()
    with pytest.raises(SceneError, match="outside the sheet"):
        s.with_value("cloth.resolution", 3)  # pins[1] holds row 3
    assert s.cloth.resolution == 26


def test_held_particles_below_the_floor_count_offsets_and_keys():
    with pytest.raises(SceneError, match=r"\[\[pins\]\]\) reach down to -0.55 m, inside the "
                                         "floor"):
        sf.apply_overrides(Scene(), ["pins=[{at=[[0,0]], keys=[[0,0,0,0],[1,0,-0.8,0]]}]"])
    # a soft pin is pushed out of the floor like any particle
    sf.apply_overrides(Scene(), ["pins=[{at=[[0,0]], offset=[0,-0.9,0], stiffness=0.5}]"])


def test_a_scene_file_with_bad_pins_exits_2_with_one_line(tmp_path, capsys):
    from cloth_tui.cli import main
    path = tmp_path / "bad.toml"
    path.write_text("[[pins]]\nrows = [0, 99]\n")
    assert main(["simulate", str(path), "--frames", "1"]) == 2
    err = capsys.readouterr().err.strip()
    assert err.count("\n") == 0 and "pins[0].rows = [0, 99] is outside the sheet" in err


def test_the_docs_example_is_a_scene_that_runs():
    from pathlib import Path

    from cloth_tui.sim.run.runner import Simulation
    page = (Path(__file__).parent.parent / "docs" / "scene-keys.md").read_text(encoding="utf-8")
    section = page.split("## Pin groups", 1)[1]
    example = section.split("```toml", 1)[1].split("```", 1)[0]
    s = sf.loads(example, "readme")
    assert len(s.pins) == 5 and s.cloth.pinned == "none"
    sim = Simulation(s)
    for _ in range(30):
        sim.advance_frame()
    assert sim.stats().finite
    lifted = 12 * 26 + 12
    assert sim.state.x[lifted, 1] == pytest.approx(sim.model.rest_positions[lifted, 1] + 0.2)


# -- properties: any [[pins]] array gives a scene and a model, or one SceneError -------------

N = 6


def ordered_pairs():
    """[first, last] with first ≤ last on the sheet, each end maybe counted from the end."""
    return st.tuples(st.integers(0, N - 1), st.integers(0, N - 1), st.booleans(),
                     st.booleans()).map(lambda t: [min(t[:2]) - N * t[2], max(t[:2]) - N * t[3]])


def tables(index, number, gap, stiffness, pair=None):
    """Strategies of [[pins]] arrays built from these value strategies."""
    cell = st.lists(index, min_size=2, max_size=2)
    pair = cell if pair is None else pair
    block = st.one_of(st.fixed_dictionaries({"rows": pair}, optional={"cols": pair}),
                      st.fixed_dictionaries({"cols": pair}))
    cells = st.fixed_dictionaries({"at": st.lists(cell, min_size=1, max_size=4)})
    vec = st.lists(number, min_size=3, max_size=3)
    # times as running sums of gaps, so they increase unless a gap is 0 (then refused)
    keys = st.lists(st.tuples(gap, vec), min_size=1, max_size=3).map(
        lambda ks: [[sum(k[0] for k in ks[:i + 1]), *ks[i][1]] for i in range(len(ks))])
    how = st.one_of(st.fixed_dictionaries({}, optional={"offset": vec, "stiffness": stiffness}),
                    st.fixed_dictionaries({"keys": keys}, optional={"stiffness": stiffness}))
    return st.lists(st.builds(lambda a, b: {**a, **b}, st.one_of(block, cells), how),
                    max_size=4)


valid = tables(st.integers(-N, N - 1), st.floats(-0.3, 0.3), st.floats(0.1, 2.0),
               st.sampled_from([1.0, 0.9, 0.5]), ordered_pairs())
anything = tables(st.integers(-N - 2, N + 1),
                  st.one_of(st.floats(-0.3, 0.3), st.floats(allow_nan=True)),
                  st.one_of(st.floats(0.1, 2.0), st.just(0.0), st.floats(allow_nan=True)),
                  st.one_of(st.sampled_from([1.0, 0.5]), st.floats(allow_nan=True)))


@settings(max_examples=100, deadline=None, suppress_health_check=[HealthCheck.too_slow])
@given(anything)
def test_any_groups_give_a_scene_or_one_scene_error(value):
    try:
        s = Scene().with_values({"cloth.resolution": N}).with_pins(value)
        build_model(s.cloth, s.behavior, s.pins)
    except SceneError as e:
        assert "\n" not in str(e)


@settings(max_examples=100, deadline=None, suppress_health_check=[HealthCheck.too_slow])
@given(valid, st.sampled_from(["none", "corners", "one_edge"]), st.booleans())
def test_groups_hold_their_particles_where_they_say(value, pinned, wave):
    """Valid tables may still disagree on a particle (refused); the rest hold as written."""
    base = Scene().with_values({"cloth.resolution": N, "cloth.pinned": pinned,
                                "behavior.wave": wave, "scene.floor": False})
    try:
        s = base.with_pins(value)
        model = build_model(s.cloth, s.behavior, s.pins)
    except SceneError as e:
        assert "both hold particle" in str(e)
        return
    assert sf.loads(sf.dumps(s), s.name) == s  # what loads, saves and loads back the same
    lay = model.pin_layout
    if lay is None:
        return
    # every hard-held particle starts where its group says, every soft one likewise
    for hold in (lay.hard, lay.soft):
        assert np.isfinite(hold.at(0.0)).all() and np.isfinite(hold.at(100.0)).all()
    for i, g in enumerate(s.pins):
        hold = lay.hard if g.stiffness == 1.0 else lay.soft
        chosen = group_particles(g, N, N, "g")
        slots = np.searchsorted(hold.index, chosen)
        assert np.array_equal(hold.index[slots], chosen)
        assert np.allclose(hold.at(0.0)[slots], model.rest_positions[chosen] + g.offset_at(0.0))
