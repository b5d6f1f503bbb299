"""The kitty encoder: decode our own escapes back to the frame."""

import base64
import re
import zlib

import numpy as np

from cloth_tui.tui.graphics import kitty

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


def test_frames_alternate_ids_place_then_delete_the_other():
    frames = kitty.KittyFrames(base_id=100)
    image = np.zeros((4, 6, 3), np.uint8)
    first, second = (parse(frames.encode(image, 10, 5)) for _ in range(2))
    for escapes, new, old in ((first, "100", "101"), (second, "101", "100")):
        actions = [(k.get("a"), k.get("i")) for k, _ in escapes if "a" in k]
        assert actions == [("t", new), ("p", new), ("d", old)]
        place = next(k for k, _ in escapes if k.get("a") == "p")
        assert (place["c"], place["r"], place["p"], place["C"]) == ("10", "5", "1", "1")


def test_query_is_a_one_pixel_image_with_an_id():
    (keys, payload), = parse(kitty.query(42))
    assert keys["a"] == "q" and keys["i"] == "42"
    assert base64.b64decode(payload) == b"\0\0\0"
