"""`cloth-tui bench` runs and reports (tiny sizes, no render): its numbers are not tested."""

import json

import pytest

from cloth_tui.cli import main


def test_bench_reports_steps_contended_and_crumpled_self_collision(capsys):
    assert main(["bench", "--quick", "--sizes", "6,8", "--no-render", "--contended",
                 "--fabric-sizes", "16", "--json"]) == 0
    r = json.loads(capsys.readouterr().out)
    for part in ("quiet", "contended"):
        rows = r[part]["step"]
        assert [s["n"] for s in rows] == [6, 8]
        for s in rows:
            for key in ("step", "kernel", "serial_loop"):
                assert s[key]["per_s_min"] <= s[key]["per_s"] <= s[key]["per_s_max"]
            assert 0.0 <= s["parallel_share"] <= 1.0
        assert r[part]["frames"]["n"] == 8 and r[part]["frames"]["adaptive"] is False
    assert "numpy" in r["quiet"]["step"][0] and "numpy" not in r["contended"]["step"][0]
    assert {row["method"] for row in r["self_collision"]} == {"naive", "hash"}
    assert all(row["pairs"] > 0 for row in r["self_collision"])  # crumpled, not flat
    assert "render" not in r
    cost = r["accuracy_cost"]
    assert cost["sizes"] == [6, 8]
    from cloth_tui.sim import solvers
    # every registered solver of constraints, the original scene's own (no keys) first
    ran = [s["solver"] for s in cost["solvers"]]
    assert ran[0] == solvers.DEFAULT and cost["solvers"][0]["keys"] == {}
    assert set(ran) == set(solvers.names(solves_constraints=True))
    assert all(s["keys"] == {"behavior.solver": s["solver"]} for s in cost["solvers"][1:])
    for solver in cost["solvers"]:
        assert [row["n"] for row in solver["rows"]] == [6, 8]
        for row in solver["rows"]:
            assert row["ms_min"] <= row["ms_per_frame"] <= row["ms_max"]
            assert row["substeps_per_frame"] >= 4  # the original scene's floor
            assert row["work_per_frame"] == row["substeps_per_frame"] * row["passes_per_substep"]
            assert isinstance(row["met"], bool) and row["worst_error"] > 0.0
        assert isinstance(solver["exponent"], float) and solver["exponent_64_256"] is None
    fabric = r["fabric_cost"]
    from cloth_tui.sim import solvers
    # every solver that takes a material, the default first, on the clipped denim sheet
    assert [f["solver"] for f in fabric["solvers"]][0] == solvers.DEFAULT
    assert {f["solver"] for f in fabric["solvers"]} == set(solvers.names(takes_material=True))
    for f in fabric["solvers"]:
        row, = f["rows"]
        assert row["n"] == 16 and row["particles"] == 17 * 17
        assert row["ms_min"] <= row["ms_per_frame"] <= row["ms_max"]
        assert row["substeps_per_frame"] >= 1 and isinstance(row["met"], bool)
    assert r["vectors"]["isa_vector_bits"] in (128, 256, 512)
    assert r["vectors"]["projection_kernel_ops"] is None  # a fresh compile: full runs only


def test_bench_text_report_labels_whole_step_and_kernel(capsys):
    assert main(["bench", "--quick", "--sizes", "5", "--no-render", "--fabric-sizes",
                 "16"]) == 0
    out = capsys.readouterr().out
    assert "whole step" in out and "kernel alone" in out and "serial numba loop" in out
    assert "simulated frames per wall second" in out and "load average" in out
    assert "Cost of accuracy" in out and "ms per frame" in out
    assert "Cost of a fabric's accuracy: 1 m of denim held by two clips" in out
    assert "vectors: the CPU offers" in out


def test_bad_sizes_and_thread_limit_are_one_line_errors(capsys, monkeypatch):
    assert main(["bench", "--sizes", "2,x"]) == 2
    assert "--sizes" in capsys.readouterr().err
    monkeypatch.setenv("CLOTH_TUI_THREADS", "lots")
    assert main(["scenes"]) == 2
    err = capsys.readouterr().err
    assert "CLOTH_TUI_THREADS" in err and "Traceback" not in err and err.count("\n") == 1


def test_gravity_cost_times_both_steps_on_one_thread(monkeypatch):
    # The thread picker chooses per step: the two steps on different thread counts made
    # gravity look cheaper than none. Both are timed on one thread; the choice comes back.
    from cloth_tui.bench import cli, timing
    from cloth_tui.sim import threads

    seen = []
    real = timing.time_calls

    def spy(fn, **kwargs):
        seen.append(threads.single_thread_forced())
        return real(fn, **{**kwargs, "block_s": 0.001, "blocks": 1})

    monkeypatch.setattr(timing, "time_calls", spy)
    cost = cli.gravity_cost(6, quick=True)
    assert seen and all(seen) and not threads.single_thread_forced()
    assert cost["bare_effects"] == ["integrate_verlet", "project_constraints", "apply_pins",
                                    "update_velocities"]


@pytest.mark.parametrize("option, sizes", [("--sizes", "100000"), ("--sizes", "600"),
                                           ("--sizes", "64,2000"), ("--cost-sizes", "513")])
def test_sizes_no_sheet_can_have_are_refused_before_any_work(capsys, monkeypatch, option,
                                                             sizes):
    import cloth_tui.bench.cli

    def never(_args):
        raise AssertionError("the bench started")

    monkeypatch.setattr(cloth_tui.bench.cli, "run_bench", never)
    assert main(["bench", option, sizes]) == 2
    err = capsys.readouterr().err
    assert err.count("\n") == 1 and "3..512 particles a side" in err and option in err


@pytest.mark.parametrize("sizes", ["20", "16,8", "512"])
def test_fabric_sizes_whose_clips_differ_are_refused_before_any_work(capsys, monkeypatch,
                                                                     sizes):
    import cloth_tui.bench.cli

    def never(_args):
        raise AssertionError("the bench started")

    monkeypatch.setattr(cloth_tui.bench.cli, "run_bench", never)
    assert main(["bench", "--fabric-sizes", sizes]) == 2
    err = capsys.readouterr().err
    assert err.count("\n") == 1 and "multiple of 16 cells" in err
