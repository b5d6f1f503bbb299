"""`cloth-tui lab`: its report, JSON and plot, and one line (exit 2) for bad input."""

import json

import pytest

from cloth_tui.cli import main
from cloth_tui.lab.cli import _ProgressLine, format_report, plot_convergence

RESULT = {  # a made-up result of study.run's form, for the text and the plot alone
    "test": "catenary", "summary": "a strip", "quantity": "sag", "unit": "m",
    "resolution_meaning": "links along the strip", "setup": "pbd", "tolerance": 0.005,
    "material": None, "elapsed_s": 1.0,
    "cases": [{"label": "one case", "expected": 0.25, "params": {}, "order": 2.0,
               "points": [{"resolution": n, "measured": 0.25 * (1 + 0.5 / n ** 2),
                           "error": 0.5 / n ** 2, "wall_s": 0.01 * n, "max_stretch": 1e-5}
                          for n in (8, 16, 32)]}]}


def test_the_report_shows_each_resolution_against_the_bound():
    text = format_report(RESULT)
    assert "expected sag 0.25 m (computed)" in text
    rows = [line.split() for line in text.splitlines() if line.strip()[:2] in ("8 ", "16", "32")]
    assert [r[0] for r in rows] == ["8", "16", "32"]
    assert [r[3] for r in rows] == ["NO", "yes", "yes"]  # 0.78 %, 0.20 %, 0.05 % vs 0.5 %
    assert "p = 2.00" in text and "stretch" in text


def test_the_plot_is_a_png(tmp_path):
    out = tmp_path / "lab.png"
    plot_convergence(RESULT, out)
    assert out.read_bytes()[:8] == b"\x89PNG\r\n\x1a\n"


def test_a_run_prints_json_and_draws(tmp_path, capsys):
    out = tmp_path / "cat.png"
    assert main(["lab", "catenary", "--resolutions", "4,8", "--json", "--plot", str(out)]) == 0
    r = json.loads(capsys.readouterr().out)
    (case,) = r["cases"]
    assert [p["resolution"] for p in case["points"]] == [4, 8]
    assert 0 < case["points"][1]["error"] < case["points"][0]["error"]  # sags more when coarse
    assert case["order"] == pytest.approx(2.0, abs=0.5)
    assert out.stat().st_size > 0


@pytest.mark.parametrize("argv, cases", [
    (["lab", "cantilever", "--resolutions", "4"], 3),
    (["lab", "peirce", "--material", "denim", "--resolutions", "4"], 2),  # warp, weft
    (["lab", "drape", "--material", "denim", "--resolutions", "11"], 1),
    (["lab", "cantilever", "--solver", "hpbd", "--resolutions", "4"], 3),
])
def test_the_bending_tests_run_from_the_command_line(argv, cases, tmp_path, capsys):
    out = tmp_path / "lab.png"
    assert main([*argv, "--json", "--plot", str(out)]) == 0
    r = json.loads(capsys.readouterr().out)
    assert len(r["cases"]) == cases and r["test"] == argv[1]
    solver = argv[argv.index("--solver") + 1] if "--solver" in argv else "xpbd"
    assert r["solver"] == solver and r["setup"].startswith(f"{solver} ")
    for case in r["cases"]:
        (point,) = case["points"]
        assert point["resolution"] == int(argv[-1]) and point["wall_s"] > 0
        if case["expected"] is not None:
            assert abs(point["error"]) < 0.05  # even at 4 links
        else:
            assert 0 < point["measured"] < 1
    assert out.read_bytes()[:8] == b"\x89PNG\r\n\x1a\n"


@pytest.mark.parametrize("argv, says", [
    (["lab", "drap"], "'drap' is not a lab test; the tests are catenary"),
    (["lab", "catenary", "--resolutions", "8,a"], "'a' is not an integer"),
    (["lab", "catenary", "--resolutions", "1000"], "outside 4–256"),
    (["lab", "cantilever", "--material", "felt"], "--material = 'felt' is not a preset"),
    # the sag and the period are the same for every fabric: naming one would be a pretence
    (["lab", "catenary", "--material", "denim"], "--material: catenary measures a strip "
                                                 "without bending stiffness"),
    (["lab", "swing", "--material", "denim"], "--material is for the tests of a material"),
    (["lab", "catenary", "--plot", "out.jpg"], "the plot is a PNG"),
    (["lab"], "the following arguments are required: test"),
    (["lab", "catenary", "--solver", "hpbd"], "--solver is for the tests of a material"),
    (["lab", "cantilever", "--solver", "pbd"], "'pbd' cannot run cantilever; choose xpbd or "
                                                "hpbd"),
])
def test_bad_input_is_one_line(argv, says, capsys):
    assert main(argv) == 2
    err = capsys.readouterr().err
    assert says in err and err.count("\n") == 1 and "Traceback" not in err


class _Notice:
    def __init__(self):
        self.finished = 0

    def finish(self):
        self.finished += 1


def test_progress_shows_on_a_terminal_only(capsys):
    notice = _Notice()
    line = _ProgressLine("catenary", notice, enabled=True)
    line(0, 2, "one case, N = 8")
    line(2, 2, "done")
    err = capsys.readouterr().err
    assert "lab catenary: 0/2 runs, now one case, N = 8…" in err
    assert err.endswith("lab catenary: 2/2 runs done\x1b[K\n")
    assert notice.finished == 2  # a compile notice's line is ended before each update
    _ProgressLine("catenary", _Notice(), enabled=False)(0, 2, "x")
    assert capsys.readouterr().err == ""


@pytest.mark.parametrize("test, resolutions, runs, why", [
    ("catenary", "170", "catenary runs N = 4–166", "behavior.substeps = 1020"),
    ("cantilever", "80", "cantilever runs N = 4–", "behavior.substeps"),
    ("peirce", "10,256", "peirce runs N = 4–", "behavior.substeps"),
    ("drape", "256", "drape runs N = 11–", "pins[0].at: 18360 entries"),
])
def test_a_resolution_whose_specimen_cannot_be_built_is_refused_before_any_run(
        test, resolutions, runs, why, capsys, monkeypatch):
    from cloth_tui.lab import study

    def never(*_args, **_kwargs):
        raise AssertionError("the study started")

    monkeypatch.setattr(study, "run", never)
    assert main(["lab", test, "--resolutions", resolutions]) == 2
    err = capsys.readouterr().err
    assert err.count("\n") == 1 and err.startswith("cloth-tui: error: --resolutions: ")
    assert runs in err and why in err


def test_the_range_it_names_is_the_range_that_builds():
    from cloth_tui.lab import registry
    from cloth_tui.lab.cli import check_resolutions
    from cloth_tui.usage import UsageError

    catenary = registry.experiment("catenary")
    check_resolutions(catenary, [4, 166], None, None)  # the ends of the range it names
    with pytest.raises(UsageError):
        check_resolutions(catenary, [167], None, None)


def test_an_error_during_the_runs_starts_a_fresh_line(capsys, monkeypatch):
    import dataclasses
    import io
    import sys

    from cloth_tui.lab import cli, hanging
    from cloth_tui.lab.study import LabError

    class Terminal(io.StringIO):
        def isatty(self):
            return True

    def diverges(case, n, material, solver):
        raise LabError(f"the strip diverged at {n} links")

    monkeypatch.setattr(hanging, "CATENARY", dataclasses.replace(hanging.CATENARY,
                                                                 measure=diverges))
    monkeypatch.setattr(cli, "check_resolutions", lambda *args: None)
    terminal = Terminal()
    monkeypatch.setattr(sys, "stderr", terminal)
    assert main(["lab", "catenary", "--resolutions", "8"]) == 2
    text = terminal.getvalue()
    assert "lab catenary: 0/1 runs, now" in text  # the progress line was showing
    assert text.endswith("\x1b[K\ncloth-tui: error: the strip diverged at 8 links\n")
