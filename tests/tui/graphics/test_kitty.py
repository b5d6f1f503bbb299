"""The kitty encoder: decode our own escapes back to the frame."""

import base64
import re
import zlib

import numpy as np

from cloth_tui.tui.graphics import kitty
from cloth_tui.tui.graphics.layout import Layout

APC = re.compile(r"\x1b_G([^;\x1b]*)(?:;([^\x1b]*))?\x1b\\")


def parse(stream: str) -> list[tuple[dict, str]]:
    out = []
    for keys, payload in APC.findall(stream):
        out.append((dict(kv.split("=", 1) for kv in keys.split(",")), payload))
    return out


def test_transmit_decodes_back_to_the_frame_in_chunks_of_at_most_4096():
    rng = np.random.default_rng(1)
    image = rng.integers(0, 256, (61, 83, 3), dtype=np.uint8)  # noise: many chunks
    escapes = parse(kitty.transmit(image, 7))
    assert len(escapes) > 2
    first = escapes[0][0]
    assert first["i"] == "7" and first["f"] == "24" and first["o"] == "z"
    assert (first["s"], first["v"]) == ("83", "61")
    assert [e[0]["m"] for e in escapes] == ["1"] * (len(escapes) - 1) + ["0"]
    assert all(len(p) <= kitty.CHUNK for _, p in escapes)
    raw = zlib.decompress(base64.b64decode("".join(p for _, p in escapes)))
    assert np.array_equal(np.frombuffer(raw, np.uint8).reshape(61, 83, 3), image)


def layout(rects, cols=10, rows=5):
    return Layout((2, 1), cols, rows, tuple(rects))


def test_frames_alternate_ids_place_then_delete_the_other():
    frames = kitty.KittyFrames(base_id=100)
    image = np.zeros((4, 6, 3), np.uint8)
    whole = layout([(0, 0, 10, 5)])
    first = parse(frames.show(frames.prepare(image, whole), whole))
    second = parse(frames.show(frames.prepare(image, whole), whole))
    third = parse(frames.show(frames.prepare(image, whole), whole))
    assert [(k.get("a"), k.get("i")) for k, _ in first if "a" in k] == [("t", "100"), ("p", "100")]
    for escapes, new, old in ((second, "101", "100"), (third, "100", "101")):
        actions = [(k.get("a"), k.get("i")) for k, _ in escapes if "a" in k]
        assert actions == [("t", new), ("p", new), ("d", old)]
        place = next(k for k, _ in escapes if k.get("a") == "p")
        assert (place["c"], place["r"], place["p"], place["C"]) == ("10", "5", "1", "1")
        assert (place["x"], place["y"], place["w"], place["h"]) == ("0", "0", "6", "4")


def test_a_covered_part_is_left_out_and_a_new_layout_moves_the_picture_without_sending_it():
    frames = kitty.KittyFrames(base_id=100)
    image = np.zeros((50, 100, 3), np.uint8)  # 10 × 10 pixels a cell
    whole = layout([(0, 0, 10, 5)])
    frames.show(frames.prepare(image, whole), whole)
    around = layout([(0, 0, 10, 3), (0, 3, 4, 2)])  # a notice at the bottom right
    out = frames.relayout(around)
    assert "a=t" not in out and "a=d,q=2,d=I" not in out
    stream = re.findall(r"\x1b\[(\d+);(\d+)H\x1b_G([^\x1b]*)\x1b\\", out)
    places = [(int(r), int(c), dict(kv.split("=") for kv in k.split(","))) for r, c, k in stream]
    assert [(r, c) for r, c, _ in places] == [(2, 3), (5, 3)]  # origin (2, 1), 1-based
    assert [(p["x"], p["y"], p["w"], p["h"], p["c"], p["r"], p["p"]) for _, _, p in places] == [
        ("0", "0", "100", "30", "10", "3", "1"), ("0", "30", "40", "20", "4", "2", "2")]
    back = parse(frames.relayout(whole))  # the notice went: one placement again
    assert [(k["a"], k.get("p")) for k, _ in back] == [("p", "1"), ("d", "2")]
    assert back[1][0]["d"] == "i"  # the placement only: the image stays
    assert frames.relayout(whole).count("a=p") == 1 and "a=d" not in frames.relayout(whole)


def test_source_rectangles_are_never_empty():
    assert kitty.source_rect((9, 4, 1, 1), 10, 5, 4, 2) == (3, 1, 1, 1)


def test_query_is_a_one_pixel_image_with_an_id():
    (keys, payload), = parse(kitty.query(42))
    assert keys["a"] == "q" and keys["i"] == "42"
    assert base64.b64decode(payload) == b"\0\0\0"
