"""The encoding thread drops frames it cannot keep up with instead of queueing them."""

import threading

import numpy as np

from cloth_tui.tui.graphics.encoder import Encoded, FrameEncoder, Job, draw_crosshair
from cloth_tui.tui.graphics.layout import Layout


class SlowCodec:
    def __init__(self):
        self.release = threading.Event()
        self.started = threading.Event()
        self.seen: list[int] = []

    def prepare(self, image, layout):
        self.started.set()
        self.release.wait(5)
        self.seen.append(int(image[0, 0, 0]))
        return f"frame{int(image[0, 0, 0])}"

    def show(self, frame, layout):
        return frame

    def relayout(self, layout):
        return ""

    def clear(self):
        return ""


def job(n):
    return Job(np.full((4, 4, 3), n, np.uint8), Layout((0, 0), 2, 2, ((0, 0, 2, 2),)), None)


def test_frames_offered_while_encoding_are_dropped_but_the_newest():
    codec = SlowCodec()
    out: list[Encoded] = []
    done = threading.Event()
    enc = FrameEncoder(codec, lambda e: (out.append(e), done.set() if len(out) == 2 else None))
    enc.start()
    try:
        enc.offer(job(1))
        assert codec.started.wait(5)
        for n in range(2, 7):  # arrive while frame 1 is being encoded
            enc.offer(job(n))
        codec.release.set()
        assert done.wait(5)
    finally:
        enc.stop()
    assert codec.seen == [1, 6] and [e.frame for e in out] == ["frame1", "frame6"]
    assert enc.dropped == 4


def test_crosshair_is_drawn_into_a_copy():
    image = np.zeros((20, 30, 3), np.uint8)
    marked = draw_crosshair(image, (0.5, 0.5), arm=3)
    assert not image.any()
    assert (marked[10, 12:19] == (255, 255, 0)).all() and (marked[7:14, 15] == (255, 255, 0)).all()
    assert marked.any(axis=-1).sum() == 13
