"""tools/benchmarks_page.py rewrites docs/benchmarks.md's measured part from one real
`cloth-tui bench --json` run (tiny sizes here) and leaves the hand-written text alone."""

from __future__ import annotations

import importlib.util
import json
import shutil
from pathlib import Path

import pytest

ROOT = Path(__file__).resolve().parent.parent
PAGE = ROOT / "docs" / "benchmarks.md"


def _tool():
    spec = importlib.util.spec_from_file_location("benchmarks_page",
                                                  ROOT / "tools" / "benchmarks_page.py")
    module = importlib.util.module_from_spec(spec)
    spec.loader.exec_module(module)
    return module


@pytest.fixture(scope="module")
def bench_json(tmp_path_factory) -> Path:
    import contextlib
    import io

    from cloth_tui.cli import main
    out = io.StringIO()
    with contextlib.redirect_stdout(out):
        assert main(["bench", "--quick", "--sizes", "6,8", "--no-render", "--contended",
                     "--json"]) == 0
    path = tmp_path_factory.mktemp("bench") / "bench.json"
    path.write_text(out.getvalue(), encoding="utf-8")
    return path


def test_the_page_has_one_generated_region():
    tool = _tool()
    text = PAGE.read_text(encoding="utf-8")
    assert text.count(tool.BEGIN) == 1 and text.count(tool.END) == 1
    assert text.index(tool.BEGIN) < text.index(tool.END)


@pytest.mark.slow  # a real bench run, if a tiny one
def test_one_bench_run_replaces_the_figures_and_keeps_the_prose(bench_json, tmp_path):
    tool = _tool()
    page = tmp_path / "benchmarks.md"
    shutil.copy(PAGE, page)
    before = page.read_text(encoding="utf-8")
    assert tool.main([str(bench_json), "--page", str(page)]) == 0
    after = page.read_text(encoding="utf-8")
    head, tail = before.split(tool.BEGIN)[0], before.split(tool.END)[1]
    assert after.startswith(head) and after.endswith(tail)  # the prose stays
    region = after.split(tool.BEGIN)[1].split(tool.END)[0]
    r = json.loads(bench_json.read_text(encoding="utf-8"))
    assert f"**Machine:** {r['machine']['cpu']}, {r['machine']['cores']} cores" in region
    assert "| 6 | " in region and "| 8 | " in region and "| 256 | " not in region
    assert "busy loop taking one core" in region  # --contended
    assert "| hpbd | 8 |" in region and "| xpbd | 6 |" in region
    # the fabric's table: --quick's 16 and 32 cells, every solver that takes a material
    fabric = region.split("### The cost of a fabric's accuracy")[1].split("###")[0]
    assert "| lbfgs | 16 |" in fabric and "| xpbd | 32 |" in fabric
    assert "`behavior.substeps = 1`" in fabric  # the default scene's settings, said
    # run again: the region is replaced, not appended to
    assert tool.main([str(bench_json), "--page", str(page)]) == 0
    assert page.read_text(encoding="utf-8") == after


def test_bad_input_is_one_line_and_exit_2(tmp_path, capsys):
    tool = _tool()
    page = tmp_path / "benchmarks.md"
    shutil.copy(PAGE, page)
    for name, content in (("empty.json", "{}"), ("list.json", "[]"), ("bad.json", "{nope")):
        (tmp_path / name).write_text(content)
        assert tool.main([str(tmp_path / name), "--page", str(page)]) == 2
        err = capsys.readouterr().err
        assert err.count("\n") == 1 and "Traceback" not in err
    assert page.read_text(encoding="utf-8") == PAGE.read_text(encoding="utf-8")
    assert tool.main([str(tmp_path / "missing.json"), "--page", str(page)]) == 2
