import asyncio

from cloth_tui.bench.render_bench import (PIXEL_CELL_PX, TERMINAL, bench_render, format_rows,
                                          preview_sizes)


def test_render_bench_returns_numbers_for_each_sheet_and_size():
    rows = bench_render(quick=True, sheets=(9,), views=(("a", (64, 48)), ("b", (48, 64))))
    assert [(r["resolution"], r["view"], r["size"]) for r in rows] == [
        (9, "a", "64x48"), (9, "b", "48x64")]
    for r in rows:
        assert r["ms_per_frame"] > 0 and r["cpu_ms_per_frame"] > 0
        assert r["ms_min"] <= r["ms_per_frame"] <= r["ms_max"]
    text = format_rows(rows)
    assert "cpu ms" in text and "view" in text


def _sizes_the_app_asks_for(tmp_path, graphics) -> list[tuple[int, int]]:
    """What the app's preview asks the renderer for in a TERMINAL-sized terminal."""
    from cloth_tui.scene import Scene
    from cloth_tui.tui.app import ClothApp
    from tests.tui.fakes import FakeRenderService

    asked = []

    class Recording(FakeRenderService):
        def resize(self, w, h):
            asked.append((w, h))
            return super().resize(w, h)

    async def go():
        app = ClothApp(Scene(), tmp_path / "caps", renderer_factory=Recording,
                       start_paused=True, graphics=graphics)
        async with app.run_test(size=TERMINAL) as pilot:
            for _ in range(100):
                if asked:
                    break
                await pilot.pause(0.02)
    asyncio.run(go())
    return asked


def test_the_bench_renders_at_the_sizes_the_apps_previews_ask_for(tmp_path):
    """The render bench's preview rows are the app's own sizes at 160×48, not a guess: the
    half-block preview (in tmux) and the kitty preview with 10×20-pixel cells."""
    from cloth_tui.tui.graphics.detect import Graphics

    views = dict(preview_sizes())
    blocks = next(size for label, size in views.items() if label.startswith("blocks"))
    kitty = next(size for label, size in views.items() if label.startswith("kitty"))
    assert _sizes_the_app_asks_for(tmp_path, None)[-1] == blocks
    assert _sizes_the_app_asks_for(tmp_path, Graphics("kitty", PIXEL_CELL_PX))[-1] == kitty
