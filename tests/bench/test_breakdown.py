"""`bench --breakdown` times each effect of a scene's step, mesh colliders included."""

import pytest

from cloth_tui.bench.breakdown import breakdown
from cloth_tui.scene_files import load


def test_the_breakdown_shows_what_the_mesh_collider_costs():
    pytest.importorskip("pyvista")
    result = breakdown(load("torus-drape"), frames=5, warmup=2)
    times = {e["effect"]: e["ms_per_frame"] for e in result["effects"]}
    assert "collide_mesh" in times and times["collide_mesh"] > 0.0


def test_the_breakdown_shows_what_tearing_costs():
    result = breakdown(load("tear"), frames=5, warmup=2)
    times = {e["effect"]: e["ms_per_frame"] for e in result["effects"]}
    assert "tear_constraints" in times and times["tear_constraints"] > 0.0
    names = [e["effect"] for e in result["effects"]]
    assert names.index("project_constraints") < names.index("tear_constraints")
