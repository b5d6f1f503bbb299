"""Where the picture may go: the preview's cells minus what covers them, as few rectangles."""

import numpy as np

from cloth_tui.tui.graphics.layout import Layout, goto, pixel_box, uncovered_rects


def painted(cols, rows, rects):
    """How many times each cell is inside one of the rectangles."""
    count = np.zeros((rows, cols), int)
    for x, y, w, h in rects:
        assert w > 0 and h > 0 and x >= 0 and y >= 0 and x + w <= cols and y + h <= rows
        count[y:y + h, x:x + w] += 1
    return count


def test_nothing_over_the_preview_is_one_rectangle_and_all_covered_is_none():
    assert uncovered_rects(100, 27, []) == ((0, 0, 100, 27),)
    assert uncovered_rects(100, 27, [(-5, -5, 200, 200)]) == ()
    assert uncovered_rects(0, 27, []) == ()


def test_a_drawer_and_a_notice_leave_the_picture_beside_them():
    # the drawer: the right 46 columns; a notice: 3 rows at the bottom right, reaching past
    # the preview's bottom (into the status line), clipped here
    rects = uncovered_rects(100, 27, [(54, 0, 46, 27), (49, 26, 49, 3)])
    assert rects == ((0, 0, 54, 26), (0, 26, 49, 1))
    rects = uncovered_rects(100, 27, [(49, 24, 49, 5)])  # no drawer: beside and right of it
    assert rects == ((0, 0, 100, 24), (0, 24, 49, 3), (98, 24, 2, 3))


def test_rectangles_cover_exactly_the_uncovered_cells_once():
    rng = np.random.default_rng(5)
    for _ in range(50):
        cols, rows = rng.integers(1, 40, 2)
        covers = [tuple(int(v) for v in rng.integers(-3, 40, 4)) for _ in range(rng.integers(0, 5))]
        covered = np.zeros((rows, cols), bool)
        for x, y, w, h in covers:
            covered[max(y, 0):max(y + h, 0), max(x, 0):max(x + w, 0)] = True
        count = painted(cols, rows, uncovered_rects(int(cols), int(rows), covers))
        assert np.array_equal(count, (~covered).astype(int))


def test_cursor_moves_and_pixel_boxes_follow_the_cells():
    layout = Layout((3, 2), 10, 5, ((0, 0, 10, 5),))
    assert goto(layout, (4, 1, 2, 2)) == "\x1b[4;8H"  # 1-based row 2+1+1, column 3+4+1
    assert pixel_box((4, 1, 2, 2), (9, 20)) == (36, 20, 54, 60)
