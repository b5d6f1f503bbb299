"""Redrawing must not make reference cycles: each redrawn line used to refer to itself
through Textual's `Strip.divide` cache, so the preview alone left ~2,400 cyclic strips a
second for the cycle collector (cloth_tui/tui/memory.py)."""

import gc

import pytest
from rich.segment import Segment
from rich.style import Style
from textual.strip import Strip

from cloth_tui.tui import memory

from .conftest import SIZE, make_app, run, until


def cyclic_garbage(make) -> list:
    """The objects `make()` leaves that only the cycle collector could free."""
    gc.collect()
    gc.set_debug(gc.DEBUG_SAVEALL)
    try:
        make()
        gc.collect()
        return list(gc.garbage)
    finally:
        gc.set_debug(0)
        gc.garbage.clear()


def a_strip() -> Strip:
    red, blue = Style(color="red"), Style(bgcolor="blue")
    return Strip([Segment("ab", red), Segment("cde", blue), Segment("f")], 6)


@pytest.mark.parametrize("cuts", [[6], [2, 6], [1, 4, 6], [3], [6, 9], [0, 6], []])
def test_divide_gives_what_textual_gives(cuts):
    memory.install_acyclic_strip_divide()
    ours = a_strip().divide(cuts)
    textual = memory._textual_divide(a_strip(), cuts)
    assert [(s.text, s.cell_length, list(s)) for s in ours] == \
           [(s.text, s.cell_length, list(s)) for s in textual]


def test_a_strip_divided_at_its_width_is_freed_without_the_cycle_collector():
    memory.install_acyclic_strip_divide()

    def divide_and_drop():
        s = a_strip()
        assert s.divide([6]) == [s]
        s.divide([2, 6])  # cached pieces are new strips: no cycle either

    assert not [o for o in cyclic_garbage(divide_and_drop) if isinstance(o, Strip)]


def test_frames_shown_in_the_app_leave_no_cyclic_strips(tmp_path):
    async def go():
        app = make_app(tmp_path, start_paused=False)
        async with app.run_test(size=SIZE) as pilot:
            await until(pilot, lambda: app.preview.frames_shown >= 3, what="first frames")

            async def show_frames():
                shown = app.preview.frames_shown
                await until(pilot, lambda: app.preview.frames_shown >= shown + 20,
                            timeout=20, what="20 more frames")

            gc.collect()
            gc.set_debug(gc.DEBUG_SAVEALL)
            try:
                await show_frames()
                gc.collect()
                garbage = [o for o in gc.garbage if isinstance(o, (Strip, Segment))]
            finally:
                gc.set_debug(0)
                gc.garbage.clear()
            assert not garbage, f"{len(garbage)} strips and segments in reference cycles"
            await pilot.press("q")

    run(go())
