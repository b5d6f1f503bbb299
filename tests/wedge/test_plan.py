"""Wedge plans: values read like --set's, checked by the scene up front; the sheet's layout."""

import pytest

from cloth_tui.scene_files import load
from cloth_tui.usage import UsageError
from cloth_tui.wedge.plan import MAX_RUNS, Layout, plan


def test_every_combination_is_a_cell_with_coerced_values():
    varies, cells = plan(load("default"), ["forces.wind=true", "forces.wind_strength=2,8",
                                           "scene.friction=0,0.5,1"])
    assert [v.values for v in varies] == [(True,), (2.0, 8.0), (0.0, 0.5, 1.0)]
    assert len(cells) == 6
    for c in cells:
        assert c.scene.forces.wind is True
        assert c.scene.forces.wind_strength == c.values["forces.wind_strength"]
        assert c.scene.scene.friction == c.values["scene.friction"]


def test_vectors_and_plain_strings_are_values():
    varies, _ = plan(load("default"), ["forces.wind_direction=[1,0,0],[0,0,1]",
                                       "cloth.pinned=none,corners"])
    assert varies[0].values == ([1.0, 0.0, 0.0], [0.0, 0.0, 1.0])
    assert varies[1].values == ("none", "corners")


def test_sheet_shapes_are_values_and_a_one_row_run_is_refused():
    varies, cells = plan(load("default"), ["cloth.size=1,[2,0.5]", "cloth.resolution=[9,4],12"])
    assert varies[0].values == (1.0, [2.0, 0.5]) and varies[1].values == ([9, 4], 12)
    assert [c.scene.cloth.grid_shape() for c in cells] == [(9, 4), (12, 12), (9, 4), (12, 4)]
    with pytest.raises(UsageError) as e:
        plan(load("default"), ["cloth.size=[1,0.01]", "cloth.resolution=26,[26,2]"])
    assert "single row" in str(e.value) and "\n" not in str(e.value)


@pytest.mark.parametrize("vary, words", [
    ("forces.nope=1,2", "unknown key"),
    ("forces.wind_strength=2,-1", "-1"),
    ("forces.wind_strength=a", "not allowed"),
    ("forces.wind_strength=2,,3", "empty value"),
    ("forces.wind_strength", "expected SECTION.KEY=V1"),
    ("forces.wind_strength=2,2.0", "listed twice"),
])
def test_bad_keys_and_values_are_one_line_before_any_work(vary, words):
    with pytest.raises(UsageError) as e:
        plan(load("default"), [vary])
    assert words in str(e.value) and "\n" not in str(e.value)


def test_a_key_varied_twice_and_too_many_runs_are_refused():
    with pytest.raises(UsageError, match="given twice"):
        plan(load("default"), ["scene.friction=0", "scene.friction=1"])
    many = ",".join(str(i) for i in range(20))
    with pytest.raises(UsageError, match=f"at most {MAX_RUNS}"):
        plan(load("default"), [f"forces.wind_strength={many}", f"forces.gravity_strength={many}"])


def test_layout_columns_rows_and_nesting():
    varies, cells = plan(load("default"), ["forces.wind=true", "forces.wind_strength=2,8",
                                           "scene.friction=0,1", "cloth.pinned=none,corners"])
    lay = Layout.of(varies)
    # one-valued keys go to the title; 1st and 3rd varied keys across, the 2nd down
    assert [v.key for v in lay.fixed] == ["forces.wind"]
    assert [v.key for v in lay.col_keys] == ["forces.wind_strength", "cloth.pinned"]
    assert [v.key for v in lay.row_keys] == ["scene.friction"]
    assert (lay.rows, lay.cols) == (2, 4)
    where = {lay.position(varies, c) for c in cells}
    assert where == {(r, c) for r in range(2) for c in range(4)}  # one cell per place
    c = next(c for c in cells if c.values == {"forces.wind": True, "forces.wind_strength": 8.0,
                                              "scene.friction": 1.0, "cloth.pinned": "none"})
    assert lay.position(varies, c) == (1, 2)  # outer key (strength) picks the block of 2
