"""The accuracy study: measured orders, unstable points, the CLI's JSON and plot."""

import dataclasses
import json
import math
from types import SimpleNamespace

import pytest

from cloth_tui.bench import accuracy as A
from cloth_tui.bench import accuracy_cli


@pytest.fixture(scope="module")
def small():
    """The quick ladders, a shorter reference run and no re-timing: orders only."""
    cfg = dataclasses.replace(A.StudyConfig.quick(), timing_budget=0.0)
    ref = A.reference(cfg)
    return cfg, ref


def test_measured_orders_match_theory(small):
    cfg, ref = small
    floor = 10 * ref["error_estimate"]
    assert ref["error_estimate"] < 1e-10
    for integ, theory in A.ORDERS.items():
        pts = [A.point(cfg, ref, integ, dt) for dt in cfg.ladders[integ]]
        o = A.measured_order(pts, floor, 0.02 * cfg.size)
        assert o["points"] >= 2, integ
        assert abs(o["order"] - theory) <= 0.3, (integ, o)


def test_unstable_point_is_marked_not_raised(small):
    cfg, ref = small
    p = A.point(cfg, ref, "explicit_euler", 1 / 60)
    assert p["stable"] is False
    assert math.isnan(p["error"]) and math.isnan(p["time"])
    q = A.point(cfg, ref, "implicit_euler", 1 / 60)
    assert q["stable"] is True and q["error"] < 0.2


def test_stability_limits_order_and_scale(small):
    cfg, _ = small
    cfg = dataclasses.replace(cfg, stability_bisections=4, stability_t_end=0.25)
    ee = A.largest_stable_dt(cfg, "explicit_euler", 200.0)
    ie = A.largest_stable_dt(cfg, "implicit_euler", 200.0)
    assert ie["note"] == "at_least" and ee["dt"] < ie["dt"]
    soft = A.largest_stable_dt(cfg, "symplectic_euler", 20.0)
    stiff = A.largest_stable_dt(cfg, "symplectic_euler", 2000.0)
    assert soft["dt"] > 3 * stiff["dt"]  # ∝ 1/√k: 10× ideally


def tiny_config():
    """A study small enough for the CLI tests, every section in it (the physical
    reference at one resolution: how it converges is the test of its own below)."""
    n = lambda *ks: tuple(1.0 / k for k in ks)  # noqa: E731
    return A.StudyConfig(
        t_end=0.1, ref_dt=1 / 8000, stiffness=2000.0,
        ladders={i: n(500, 1000) for i in A.ORDERS} | {"explicit_euler": n(60, 2000)},
        pbd_dts=n(240,), pbd_iterations=(2,), stability_stiffness=(20.0, 200.0, 2000.0),
        stability_t_end=0.05, stability_bisections=1, sag_iterations=(1, 4), sag_t_end=0.2,
        timing_budget=0.0, cantilever_links=(4,))


def test_cli_json_and_plot(tmp_path, monkeypatch, capsys):
    monkeypatch.setattr(A.StudyConfig, "quick", classmethod(lambda cls: tiny_config()))
    out = tmp_path / "wp.png"
    args = SimpleNamespace(json=True, quick=True, plot=str(out))
    assert accuracy_cli.run_accuracy(args) == 0
    data = json.loads(capsys.readouterr().out)
    assert set(data) >= {"points", "orders", "stability", "reference", "sag", "physical"}
    keys = {"method", "dt", "iterations", "error", "max_error", "time", "stable", "stretch",
            "energy_drift"}
    assert all(keys <= set(p) for p in data["points"])
    bad = [p for p in data["points"] if p["method"] == "explicit_euler" and p["dt"] > 0.01]
    assert bad and bad[0]["stable"] is False and bad[0]["error"] is None
    assert set(data["orders"]) == set(A.ORDERS)
    assert set(data["stability"]["methods"]) == set(A.ORDERS)
    assert out.read_bytes()[:8] == b"\x89PNG\r\n\x1a\n"
    assert not list(tmp_path.glob(".*.part"))


def test_cli_text(monkeypatch, capsys):
    monkeypatch.setattr(A.StudyConfig, "quick", classmethod(lambda cls: tiny_config()))
    assert accuracy_cli.run_accuracy(SimpleNamespace(json=False, quick=True, plot=None)) == 0
    text = capsys.readouterr().out
    assert "Measured order" in text and "Stability map" in text and "Settled sag" in text
    assert "Physical reference" in text and any(line.startswith("pbd") and "not run:" in line
                                                for line in text.splitlines())


def test_plot_needs_png(tmp_path):
    from cloth_tui.cli import main
    assert main(["accuracy", "--quick", "--plot", str(tmp_path / "x.jpg")]) == 2


def test_the_physical_reference_is_the_elastica_per_solver():
    """Only a solver that takes the material runs it (xpbd; the others are listed with the
    reason), and its error against the elastica falls with the resolution."""
    from cloth_tui.bench import accuracy_physical as P

    links = (4, 8)
    p = P.physical_study(links, A.run_serially(P.physical_calls(links)))
    from cloth_tui.scene import SOLVERS

    ran = {q["solver"] for q in p["points"] + p["unsettled"]}
    assert "xpbd" in ran and {"pbd", "springs"} <= set(p["not_run"])
    assert ran | set(p["not_run"]) == set(SOLVERS) and not ran & set(p["not_run"])
    assert all("did not settle" in q["unsettled"] for q in p["unsettled"])
    assert all("needs behavior.solver" in why for why in p["not_run"].values())
    coarse, fine = (next(q for q in p["points"] if q["links"] == n and q["solver"] == "xpbd")
                    for n in links)
    assert abs(fine["error"]) < abs(coarse["error"]) < 0.05
    assert fine["wall_s"] > 0 and p["expected"] == pytest.approx(0.6406, abs=1e-4)
