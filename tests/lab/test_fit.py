"""`cloth-tui lab fit`: a fabric from measurements, written as a [material] and proven by
the lab's own tests (the virtual Peirce test; the drape test where a coefficient is given)."""

import json
import math

import pytest

from cloth_tui.cli import main
from cloth_tui.lab import fit
from cloth_tui.lab.study import LabError
from cloth_tui.materials.schema import strip_rigidities
from cloth_tui.scene_files import load

G = 9.81


@pytest.mark.parametrize("text, stretch", [
    ("5 % at 10 N/5 cm", (4000.0, 4000.0)),        # 200 N/m over 0.05
    ("5,8 % at 10 N/5 cm", (4000.0, 2500.0)),      # warp, weft
    ("2%@3N/mm", (150000.0, 150000.0)),            # 3000 N/m over 0.02
    ("10 % at 2 N/cm", (2000.0, 2000.0)),          # a width of one cm
])
def test_an_extension_at_a_load_is_the_tension_per_width_over_the_strain(text, stretch):
    assert fit.parse_extension(text) == pytest.approx(stretch)


@pytest.mark.parametrize("parse, text, says", [
    (fit.parse_extension, "5 at 10 N/5 cm", "is not an extension at a load"),
    (fit.parse_extension, "5 % at 10 kg", "is not a load per strip width"),
    (fit.parse_extension, "150 % at 10 N/5 cm", "below 100 %"),
    (fit.parse_extension, "0 % at 10 N/5 cm", "is not an extension in %"),
    (fit.parse_bending_lengths, "2.4,1.9,3", "has 3 values"),
    (fit.parse_bending_lengths, "-2", "is not a positive length"),
    (fit.parse_density, "nan", "is not a positive number of g/m²"),
    (fit.parse_drape, "1.2", "is not below 1"),
    (fit.parse_drape, "120 %", "is not below 1"),
])
def test_a_measurement_that_is_none_is_refused(parse, text, says):
    with pytest.raises(LabError, match=says):
        parse(text)


def test_the_closed_form_is_peirces_rigidity_per_direction():
    one = fit.Measurements(0.25, (0.024,), None, None)
    table, notes = fit.closed_form(one)
    assert table["bending"] == pytest.approx(0.25 * G * 0.024 ** 3, rel=1e-5)
    assert table["areal_density"] == 0.25
    assert not any("bending by direction" in n for n in notes)
    two = fit.Measurements(0.25, (0.024, 0.019), (4000.0, 2500.0), None)
    table, notes = fit.closed_form(two)
    assert table["bending"] == pytest.approx([0.25 * G * 0.024 ** 3, 0.25 * G * 0.019 ** 3],
                                             rel=1e-5)
    assert table["stretch"] == [4000.0, 2500.0]
    assert any("bending by direction" in n and "√(B_warp·B_weft)" in n for n in notes)


def _fake_drape(monkeypatch, drape_of_shear):
    calls = []

    def drape(material, resolution, solver):
        calls.append(material.shear)
        return {"drape": drape_of_shear(material.shear), "folds": 6, "wall_s": 0.0}

    monkeypatch.setattr(fit, "drape_coefficient", drape)
    return calls


def _smooth(shear):  # of the form the drape test shows: 0.24 at 0.05 N/m, 0.70 at 1000
    return 0.24 + 0.46 / (1 + math.exp(-(math.log(shear) - 1.0) / 1.6))


@pytest.mark.parametrize("aim", [0.3, 0.45, 0.6])
def test_the_drape_search_reaches_its_aim_in_a_few_runs(aim, monkeypatch):
    calls = _fake_drape(monkeypatch, _smooth)
    table = {"areal_density": 0.25, "stretch": [1000.0, 1000.0], "shear": 26.7,
             "bending": 2e-5}
    fitted, runs = fit.fit_drape(table, aim, 25, "xpbd", lambda _: None)
    assert abs(_smooth(fitted["shear"]) - aim) <= fit.DRAPE_AIM
    assert len(runs) == len(calls) <= 6
    assert {k: v for k, v in fitted.items() if k != "shear"} == \
        {k: v for k, v in table.items() if k != "shear"}


def test_a_drape_beyond_reach_stops_at_the_end_of_the_range_with_the_nearest(monkeypatch):
    _fake_drape(monkeypatch, _smooth)
    table = {"areal_density": 0.25, "stretch": [300.0, 500.0], "shear": 26.7,
             "bending": 2e-5}
    fitted, runs = fit.fit_drape(table, 0.95, 25, "xpbd", lambda _: None)
    assert fitted["shear"] == pytest.approx(300.0)   # the smaller stretch: the range's top
    assert len(runs) < fit.DRAPE_MAX_RUNS
    fitted, runs = fit.fit_drape(table, 0.05, 25, "xpbd", lambda _: None)
    assert fitted["shear"] == pytest.approx(fit.SHEAR_MIN)


def test_lab_fit_writes_a_material_whose_peirce_test_gives_back_the_length(tmp_path, capsys):
    out = tmp_path / "fabric.toml"
    assert main(["lab", "fit", "--density", "250", "--bending-length", "2.4",
                 "--extension", "5 % at 10 N/5 cm", "-o", str(out), "--json"]) == 0
    captured = capsys.readouterr()
    r = json.loads(captured.out)
    scene = load(out)  # the default scene (its two clips, its solver) with the fabric
    assert len(scene.pins) == 2 and scene.behavior.solver == load("default").behavior.solver
    written = scene.material.material
    assert written.bending == pytest.approx(0.25 * G * 0.024 ** 3, rel=1e-5)
    assert (written.stretch_warp, written.stretch_weft) == (4000.0, 4000.0)
    assert written.areal_density == 0.25
    (peirce,) = r["proof"]["peirce"]   # one length: an isotropic fabric, one strip
    assert peirce["bending_length"] == pytest.approx(0.024, rel=0.02)
    assert r["proof"]["ok"] and r["output"] == str(out)
    assert "lab fit: proof: virtual Peirce test" in captured.err   # progress on stderr


def test_lab_fit_with_warp_and_weft_gives_back_each_length_along_its_strip(tmp_path, capsys):
    """The written fabric bends by direction: the virtual Peirce strip cut along the warp
    (x) gives back 2.4 cm and the one cut along the weft (z) 1.9 cm."""
    out = tmp_path / "fabric.toml"
    assert main(["lab", "fit", "--density", "250", "--bending-length", "2.4,1.9",
                 "-o", str(out), "--json"]) == 0
    r = json.loads(capsys.readouterr().out)
    written = load(out).material.material
    assert strip_rigidities(written) == pytest.approx((0.25 * G * 0.024 ** 3,
                                                       0.25 * G * 0.019 ** 3), rel=1e-5)
    warp, weft = r["proof"]["peirce"]
    assert (warp["direction"], weft["direction"]) == ("warp", "weft")
    assert warp["bending_length"] == pytest.approx(0.024, rel=0.02)
    assert weft["bending_length"] == pytest.approx(0.019, rel=0.02)
    assert r["proof"]["ok"]


def test_lab_fit_prints_the_pair_and_both_strips(capsys):
    assert main(["lab", "fit", "--density", "250", "--bending-length", "2.4,1.9"]) == 0
    text = capsys.readouterr().out
    assert "bending = [3.39034e-05, 1.68217e-05]" in text  # no -o: the section is printed
    lines = [s for s in text.splitlines() if "virtual Peirce test" in s]
    assert [s.split("strip along the ")[1].split(")")[0] for s in lines] == ["warp", "weft"]
    for line, length in zip(lines, (2.4, 1.9)):
        measured = float(line.split("bending length ")[1].split(" cm")[0])
        assert measured == pytest.approx(length, rel=0.02)
        assert line.endswith("within 2%: yes")


def test_lab_fit_writes_a_whole_scene_with_the_fabric(tmp_path, monkeypatch):
    proven = []
    monkeypatch.setattr(fit, "prove", lambda material, *a: proven.append(material) or
                        {"peirce": [{"direction": "warp", "overhang": 0.04,
                                     "bending_length": 0.02, "expected": 0.02,
                                     "error": 0.0, "tolerance": 0.02, "ok": True}],
                         "drape": None, "ok": True})
    out = tmp_path / "sphere-fabric.toml"
    assert main(["lab", "fit", "--density", "180", "--bending-length", "2", "--scene",
                 "sphere", "-o", str(out)]) == 0
    scene = load(out)
    assert scene.scene.object == "sphere"
    assert scene.material.material.bending == pytest.approx(0.18 * G * 0.02 ** 3, rel=1e-5)
    assert proven == [scene.material.material]  # the proof runs the fabric as written


@pytest.mark.parametrize("argv, says", [
    (["--bending-length", "2.4"], "lab fit needs --density"),
    (["--density", "250"], "lab fit needs --bending-length"),
    (["--density", "heavy", "--bending-length", "2"], "--density: 'heavy' is not"),
    (["--density", "250", "--bending-length", "2", "--extension", "5 %"],
     "--extension: '5 %' is not an extension at a load"),
    (["--density", "250", "--bending-length", "2", "--drape", "2"],
     "--drape: '2' is not below 1"),
    (["--density", "250", "--bending-length", "2", "--drape-resolution", "25"],
     "--drape-resolution: is for --drape"),
    (["--density", "250", "--bending-length", "2", "--drape", "0.4", "--drape-resolution",
      "5"], "--drape-resolution: 5 is outside 11–256"),
    (["--density", "250", "--bending-length", "2", "--scene", "sphere"],
     "--scene: needs -o FILE.toml"),
    (["--density", "250", "--bending-length", "2", "--scene", "tear", "-o", "x.toml"],
     "--scene tear: [material] (custom) needs behavior.solver"),
    (["--density", "250", "--bending-length", "2", "-o", "fabric.json"],
     "unsupported file type"),
    (["--density", "250", "--bending-length", "2", "--material", "felt"], "not a preset"),
    (["--density", "250", "--bending-length", "2", "--solver", "pbd"], "'pbd' cannot run"),
    (["--density", "250", "--bending-length", "2", "--resolutions", "10"],
     "--resolutions: is for the lab's tests"),
    (["--density", "250", "--bending-length", "0.001"],
     "--bending-length: the virtual Peirce test cannot run this fabric"),
])
def test_bad_input_to_lab_fit_is_one_line_before_any_run(argv, says, capsys, monkeypatch,
                                                         tmp_path):
    def never(*_args, **_kwargs):
        raise AssertionError("a run started")

    monkeypatch.chdir(tmp_path)
    monkeypatch.setattr(fit, "fit_drape", never)
    monkeypatch.setattr(fit, "prove", never)
    assert main(["lab", "fit", *argv]) == 2
    err = capsys.readouterr().err
    assert says in err and err.count("\n") == 1 and "Traceback" not in err
    assert not (tmp_path / "x.toml").exists()


def test_the_other_lab_tests_refuse_fits_flags(capsys):
    assert main(["lab", "peirce", "--density", "250"]) == 2
    err = capsys.readouterr().err
    assert "--density: is for `cloth-tui lab fit`, not lab peirce" in err


@pytest.mark.slow
def test_lab_fit_with_a_drape_coefficient_drapes_as_measured(tmp_path, capsys):
    out = tmp_path / "fabric.toml"
    assert main(["lab", "fit", "--density", "250", "--bending-length", "2.4,1.9",
                 "--drape", "0.45", "-o", str(out), "--json"]) == 0
    captured = capsys.readouterr()
    r = json.loads(captured.out)
    drape = r["proof"]["drape"]
    assert abs(drape["drape"] - 0.45) <= 0.03 and drape["resolution"] == 25
    assert load(out).material.material.shear == r["material"]["shear"]
    assert r["material"]["shear"] != r["drape_runs"][0]["shear"]  # the search moved it
    assert "lab fit: drape run 1" in captured.err


def test_a_drape_the_fabric_cannot_reach_is_written_reported_and_exits_1(tmp_path, capsys,
                                                                          monkeypatch):
    _fake_drape(monkeypatch, _smooth)
    monkeypatch.setattr(fit, "peirce_bending_lengths", lambda material, solver: [{
        "direction": "warp", "overhang": 0.048, "bending_length": 0.024, "runs": 3,
        "wall_s": 0.0}])
    out = tmp_path / "fabric.toml"
    assert main(["lab", "fit", "--density", "250", "--bending-length", "2.4", "--drape",
                 "0.9", "-o", str(out)]) == 1
    captured = capsys.readouterr()
    drape_line = next(s for s in captured.out.splitlines() if "drape test" in s)
    assert drape_line.startswith("  drape test (25 particles across)") and ": NO" in drape_line
    assert captured.err.splitlines()[-1] == ("cloth-tui: lab fit: the fitted fabric does not "
                                             "pass its proof (see the report)")
    # written all the same, with the nearest: the range's top, denim's smaller stretch
    assert load(out).material.material.shear == pytest.approx(410.704, rel=1e-5)
