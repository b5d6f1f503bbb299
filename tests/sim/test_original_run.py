"""The original's numbers are kept: a scene without a material runs as it did before the
material was wired in (tests/sim/data/original_runs.json, made with the code before)."""

import json
from pathlib import Path

import pytest

from . import original_run

STORED = json.loads((Path(__file__).parent / "data" / "original_runs.json").read_text())


@pytest.mark.parametrize("name", sorted(original_run.RUNS))
def test_a_scene_without_a_material_reproduces_the_stored_run(name):
    now, then = original_run.summary(name), STORED[name]
    assert now["steps"] == then["steps"]
    assert now["centre"] == pytest.approx(then["centre"], rel=1e-12, abs=1e-14)
    assert now["sum"] == pytest.approx(then["sum"], rel=1e-12, abs=1e-12)
    assert now["sum_of_squares"] == pytest.approx(then["sum_of_squares"], rel=1e-12)


def test_material_original_is_the_scene_without_one():
    from cloth_tui.scene_files import load

    scene = original_run.scene_of("original")
    assert scene == load("original").with_values({"material": "original",
                                                  "behavior.solver": "pbd"})
