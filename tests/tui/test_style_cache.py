"""The preview's style cache stays bounded however many colours a turning camera shows, and
keeps the styles a frame keeps using."""

import io
import random

import pytest
from rich.color import ColorSystem
from rich.console import Console
from rich.segment import Segment
from rich.style import Style
from textual.strip import Strip

from cloth_tui.tui.preview import RecentCache, StyleCache


def pair(top: int, bottom: int) -> int:
    return (top << 24) | bottom


def test_styles_have_the_packed_colours():
    style = StyleCache()(pair(0x102030, 0xA0B0C0))
    assert style.color.triplet == (0x10, 0x20, 0x30)
    assert style.bgcolor.triplet == (0xA0, 0xB0, 0xC0)


def test_bounded_by_two_generations_of_its_limit():
    cache = StyleCache(limit=256)
    rng = random.Random(3)
    for _ in range(20_000):  # ever new colours, as when the camera keeps turning
        cache(pair(rng.randrange(1 << 24), rng.randrange(1 << 24)))
        assert len(cache) <= 2 * 256


def test_what_each_frame_uses_stays_cached():
    made = []
    cache = RecentCache(lambda k: made.append(k) or object(), limit=100)
    frame = list(range(60))  # a frame's colour pairs, drawn again and again
    rng = random.Random(5)
    for n in range(200):
        for key in frame:
            cache(key)
        for _ in range(30):  # new pairs in every frame, seen once
            cache(1000 + rng.randrange(1 << 30))
    assert made.count(0) == 1 and all(made.count(k) == 1 for k in frame)


def test_colours_are_shared_between_styles():
    cache = StyleCache()
    a, b = cache(pair(0x111111, 0x222222)), cache(pair(0x111111, 0x333333))
    assert a.color is b.color


def test_the_default_cache_holds_a_few_megabytes_at_most():
    """Cleared only at 50,000 styles (each with its own two colours), it grew to ~30 MB."""
    import tracemalloc

    rng = random.Random(7)
    keys = [pair(rng.randrange(1 << 24), rng.randrange(1 << 24)) for _ in range(40_000)]
    tracemalloc.start()
    try:
        cache = StyleCache(color_system=ColorSystem.TRUECOLOR)
        base = tracemalloc.get_traced_memory()[0]
        for key in keys:
            cache(key)
        peak = tracemalloc.get_traced_memory()[1] - base
    finally:
        tracemalloc.stop()
    assert peak < 7.5e6, f"{peak / 1e6:.1f} MB"


def random_pairs(n: int, seed: int) -> list[int]:
    rng = random.Random(seed)
    return [pair(rng.randrange(1 << 24), rng.randrange(1 << 24)) for _ in range(n)]


@pytest.mark.parametrize("name, system", [("truecolor", ColorSystem.TRUECOLOR),
                                          ("256", ColorSystem.EIGHT_BIT),
                                          ("standard", ColorSystem.STANDARD)])
def test_styles_draw_as_textual_would_draw_them(name, system):
    console = Console(file=io.StringIO(), color_system=name, force_terminal=True)
    cache = StyleCache(color_system=system)
    for key in random_pairs(200, seed=11):
        top, bottom = key >> 24, key & 0xFFFFFF
        plain = Style(color=f"#{top:06x}", bgcolor=f"#{bottom:06x}")
        assert Strip([Segment("▀▀", cache(key))]).render(console) == \
               Strip([Segment("▀▀", plain)]).render(console)


def test_drawing_new_colours_leaves_textuals_class_wide_cache_alone():
    """That cache (16,384 styles) would otherwise keep every pair ever shown alive."""
    console = Console(file=io.StringIO(), color_system="truecolor", force_terminal=True)
    cache = StyleCache(color_system=ColorSystem.TRUECOLOR)
    before = Strip.render_ansi.cache_info().currsize
    for key in random_pairs(500, seed=13):
        Strip([Segment("▀", cache(key))]).render(console)
    assert Strip.render_ansi.cache_info().currsize == before
