"""The [material] section's validation: presets and overrides, required keys, and one-line
errors naming the key and what is allowed."""

import pytest

from cloth_tui.materials.errors import MaterialError
from cloth_tui.materials.presets import get_preset
from cloth_tui.materials.schema import bending_length, material_from_table


def test_a_preset_gives_every_value_and_keys_override_it():
    denim = get_preset("denim")
    m = material_from_table({"preset": "denim"})
    assert (m.areal_density, m.stretch_warp, m.stretch_weft, m.shear, m.bending) == \
        (denim.areal_density, denim.stretch_warp, denim.stretch_weft, denim.shear,
         denim.bending)
    assert m.damping == 0.0 and m.tear_strength is None and m.preset == "denim"
    m = material_from_table({"preset": "denim", "bending": 2e-4, "stretch": 500,
                             "damping": 0.7, "tear_strength": 3000})
    assert m.bending == 2e-4 and m.stretch_warp == m.stretch_weft == 500.0
    assert m.damping == 0.7 and m.tear_strength == 3000.0 and m.areal_density == 0.324


def test_a_material_without_a_preset_gives_its_four_numbers():
    m = material_from_table({"areal_density": 0.15, "stretch": [300, 200], "shear": 20,
                             "bending": 1e-5})
    assert (m.stretch_warp, m.stretch_weft, m.preset) == (300.0, 200.0, "")
    with pytest.raises(MaterialError, match=r"missing: shear, bending\); or set "
                                            r"material.preset"):
        material_from_table({"areal_density": 0.15, "stretch": 300})


@pytest.mark.parametrize("table, says", [
    ({"preset": "velvet"}, "material.preset = 'velvet' is not a preset"),
    ({"preset": 3}, "material.preset = 3 is not allowed"),
    ({"preset": "denim", "colour": "red"}, "unknown key material.colour"),
    ({"preset": "denim", "areal_density": 0}, "areal_density = 0 is not allowed"),
    ({"preset": "denim", "areal_density": True}, "areal_density = True"),
    ({"preset": "denim", "stretch": [1, 2, 3]}, "must be [warp, weft]"),
    ({"preset": "denim", "stretch": [1, "2"]}, "stretch = '2'"),
    ({"preset": "denim", "shear": float("inf")}, "not a finite number"),
    ({"preset": "denim", "bending": 10 ** 400}, "an integer of about 401 digits"),
    ({"preset": "denim", "damping": -0.1}, "0 ≤ value ≤ 1000 (1/s)"),
    ({"preset": "denim", "tear_strength": 0}, "0 < value"),
    ("denim", "[material] must be a table"),
])
def test_a_bad_material_is_one_line_naming_the_key(table, says):
    with pytest.raises(MaterialError) as e:
        material_from_table(table)
    assert says in str(e.value)
    assert "\n" not in str(e.value)


def test_a_control_character_in_a_key_is_escaped():
    with pytest.raises(MaterialError) as e:
        material_from_table({"preset": "denim", "\x1b[2J": 1})
    assert "\x1b" not in str(e.value) and "\\x1b" in str(e.value)


def test_the_bending_length_is_peirces():
    m = material_from_table({"areal_density": 0.2, "stretch": 100, "shear": 10,
                             "bending": 0.2 * 9.81 * 0.02 ** 3})
    assert bending_length(m) == pytest.approx(0.02)


def test_a_bending_pair_bends_by_direction_and_an_equal_pair_is_isotropic():
    base = {"areal_density": 0.25, "stretch": 1000.0, "shear": 20.0}
    m = material_from_table(base | {"bending": [4e-5, 1e-5]})
    folds = m.bending_by_direction
    assert (folds.fold_90, folds.fold_0) == (4e-5, 1e-5)   # the warp strip curves along x
    # the bias: twist stencils of the overall √(B_warp·B_weft), (√warp + √weft)²/4
    assert folds.grid_rigidities() == pytest.approx((4e-5, 1e-5, 2e-5))
    assert folds.along(45.0) == pytest.approx(folds.fold_45) == pytest.approx(2.25e-5)
    same = material_from_table(base | {"bending": [2e-5, 2e-5]}).bending_by_direction
    assert same.grid_rigidities() == pytest.approx((2e-5, 2e-5, 2e-5))
    assert [same.along(a) for a in (0, 30, 45, 90)] == pytest.approx([2e-5] * 4)
    # beside a measured preset the pair replaces its folds
    denim = material_from_table({"preset": "denim", "bending": [4e-5, 1e-5]})
    assert denim.bending_by_direction == folds and denim.stretch_curves is not None
