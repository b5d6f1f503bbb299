"""`cloth-tui materials`: every fabric preset, its values with their units, and its source."""

import json

from cloth_tui.cli import main
from cloth_tui.materials.presets import load_presets


def test_the_table_lists_every_preset_with_its_values_units_and_source(capsys):
    assert main(["materials"]) == 0
    out = capsys.readouterr().out
    head = out.splitlines()[0]
    for unit in ("g/m²", "N/m", "µN·m"):
        assert unit in head
    rows = {line.split()[0]: line for line in out.splitlines()[1:] if line.strip()}
    sources = out.split("Sources:")[1]
    for name, p in load_presets().items():
        assert name in rows, f"{name} is not listed"
        assert f"{1e3 * p.areal_density:.4g}" in rows[name]  # its weight in g/m²
        if p.alias_of:
            assert f"= {p.alias_of}" in rows[name]  # its source is its row's
        else:
            assert f"  {name}: {p.source}" in sources


def test_json_gives_every_preset_in_si_units_with_its_source(capsys):
    assert main(["materials", "--json"]) == 0
    doc = json.loads(capsys.readouterr().out)
    assert doc["units"]["areal_density"] == "kg/m²" and doc["units"]["bending"] == "N·m"
    by_name = {r["name"]: r for r in doc["presets"]}
    assert set(by_name) == set(load_presets())
    for name, p in load_presets().items():
        r = by_name[name]
        assert r["source"] == p.source and r["source"]
        assert (r["areal_density"], r["stretch_warp"], r["bending"]) == \
            (p.areal_density, p.stretch_warp, p.bending)
    denim = by_name["denim"]
    assert denim["alias_of"] == "wang2011-11oz-black-denim"
    assert denim["bending_90"] > denim["bending"]  # measured by direction
    assert denim["stretch_warp_strained"] > denim["stretch_warp"]  # stiffens with strain
    assert by_name["silk"]["estimate"] and by_name["silk"]["bending_90"] is None


def test_help_names_the_command(capsys):
    assert main(["--help"]) == 0
    assert "materials" in capsys.readouterr().out
    assert main(["materials", "--help"]) == 0
    assert "fabric presets" in capsys.readouterr().out
