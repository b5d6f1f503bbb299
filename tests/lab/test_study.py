"""The lab's shared parts: the resolutions a user gives, the fitted order, the material."""

import pytest

from cloth_tui.lab import hanging, study
from cloth_tui.lab.registry import TESTS, experiment


def test_resolutions_are_parsed_sorted_and_checked():
    assert study.parse_resolutions("32, 8,16", hanging.CATENARY) == [8, 16, 32]
    for bad, says in [("8,x", "'x' is not an integer"), ("2", "outside 4–256"),
                      ("8,8", "given twice"), ("100000", "outside"), ("", "not an integer")]:
        with pytest.raises(study.LabError, match=says):
            study.parse_resolutions(bad, hanging.CATENARY)


def test_the_fitted_order_of_known_errors():
    pts = [{"resolution": n, "error": 0.3 / n ** 2} for n in (8, 16, 32)]
    assert study.fitted_order(pts) == pytest.approx(2.0)
    signs = [{"resolution": n, "error": (-1) ** n * 0.3 / n} for n in (8, 9, 10)]
    assert study.fitted_order(signs) == pytest.approx(1.0)
    assert study.fitted_order(pts[:1]) is None
    assert study.fitted_order([{"resolution": 8, "error": None}] * 3) is None


def test_a_material_by_preset_name():
    m = study.lab_material("denim")
    assert m.preset == "denim" and m.areal_density > 0 and m.bending > 0
    assert study.lab_material(None) is None
    with pytest.raises(study.LabError, match="'felt' is not a preset; the presets are"):
        study.lab_material("felt")


def test_every_listed_test_loads():
    for name in TESTS:
        assert experiment(name).name == name
    with pytest.raises(study.LabError, match="'drap' is not a lab test; the tests are"):
        experiment("drap")
