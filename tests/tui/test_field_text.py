"""A field shows its value exactly enough to read back as the same value, so Enter on an
unchanged field is a no-op: no rebuild, no refusal (issue 19)."""

from hypothesis import given
from hypothesis import strategies as st
from textual.widgets import Input

from cloth_tui.scene import Scene
from cloth_tui.tui.panels import format_value, parse_text, widget_id

from .conftest import SIZE, make_app, notifications, run

finite = st.floats(allow_nan=False, allow_infinity=False)  # subnormals, huge, tiny, ±0


@given(finite)
def test_float_text_reads_back_exactly(x):
    assert parse_text("cloth.mass", format_value(x)) == x


@given(st.lists(finite, min_size=3, max_size=3))
def test_vector_text_reads_back_exactly(v):
    assert parse_text("forces.wind_direction", format_value(v)) == v


@given(st.integers(min_value=0, max_value=2**63 - 1))
def test_integer_text_reads_back_exactly(n):
    assert parse_text("behavior.seed", format_value(n)) == n


def test_whole_floats_stay_short():
    assert format_value(1.0) == "1" and format_value(0.5) == "0.5" and format_value(1e20) == "1e+20"


UNCHANGED = {"cloth.mass": 0.123456789, "behavior.damping": 0.9999999,
             "behavior.seed": 2**63 - 1}


def test_enter_on_an_unchanged_field_changes_nothing(tmp_path):
    scene = Scene()
    for dotted, value in UNCHANGED.items():
        scene = scene.with_value(dotted, value)

    async def go():
        app = make_app(tmp_path, scene)
        async with app.run_test(size=SIZE) as pilot:
            for dotted in UNCHANGED:
                field = app.query_one("#" + widget_id(dotted), Input)
                field.focus()
                await pilot.pause()
                await pilot.press("enter")
                await pilot.pause()
            assert app.scene is scene, "an unchanged field was set again"
            assert not notifications(app)
    run(go())
