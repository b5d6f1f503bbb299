"""The preset list as the app shows it, and the scene keys a fabric replaces."""

from cloth_tui.materials.catalogue import KINDS, preset_rows, replaced_keys
from cloth_tui.materials.presets import load_presets
from cloth_tui.materials.schema import material_from_table


def test_every_preset_is_listed_with_its_kind_weight_and_source():
    rows = {r.name: r for r in preset_rows()}
    assert set(rows) == set(load_presets())
    denim = rows["denim"]
    assert (denim.kind, round(denim.grams_per_m2), denim.source) == \
        ("11 oz twill denim", 324, "Wang 2011")
    assert rows["silk"].source == "estimate"
    # every row of the table has a kind of its own (a new row must be given one)
    for name, preset in load_presets().items():
        assert (preset.alias_of or name) in KINDS, name


def test_familiar_names_come_first_then_estimates_then_measured_rows():
    rows = preset_rows()
    kinds = [("alias" if r.is_alias else "estimate" if r.preset.estimate else "measured")
             for r in rows]
    assert kinds == sorted(kinds, key=["alias", "estimate", "measured"].index)
    assert rows[0].name == "denim"


def test_a_fabric_replaces_mass_damping_and_compliance_and_tear_stretch_only_with_strength():
    plain = replaced_keys(material_from_table({"preset": "denim"}))
    assert {"cloth.mass", "behavior.damping", "behavior.compliance"} <= set(plain)
    assert "behavior.tear_stretch" not in plain and "forces.gravity_strength" not in plain
    strong = replaced_keys(material_from_table({"preset": "denim", "tear_strength": 900.0}))
    assert "behavior.tear_stretch" in strong
