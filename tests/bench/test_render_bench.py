from cloth_tui.bench.render_bench import bench_render, format_rows


def test_render_bench_returns_numbers_for_each_sheet_and_size():
    rows = bench_render(quick=True, sheets=(9,), sizes=((64, 48), (48, 64)))
    assert [(r["resolution"], r["size"]) for r in rows] == [(9, "64x48"), (9, "48x64")]
    for r in rows:
        assert r["ms_per_frame"] > 0 and r["cpu_ms_per_frame"] > 0
        assert r["ms_min"] <= r["ms_per_frame"] <= r["ms_max"]
    assert "cpu ms" in format_rows(rows)
