"""The measured-fabric table: every row is in SI units with a source, the measured rows
agree with the published ranges and bending lengths, and a malformed table is refused in
one line."""

import math

import pytest

from cloth_tui.materials.errors import MaterialError
from cloth_tui.materials.presets import get_preset, load_presets, parse_presets

WANG = [name for name, p in load_presets().items()
        if name.startswith("wang2011-") and not p.alias_of]

# Bending length c = (k/(ρ_A g))^⅓ of each Wang 2011 fabric as tabulated in the project's
# reference notes (shared/reference/physical-cloth.md), computed there from the same files
# with the stored bending k read as B: a check that density and bending were carried over
# in kg/m² and N·m (the table's B is k/4, see test_arcsim.py).
REFERENCE_BENDING_LENGTH_CM = {
    "gray-interlock": 2.33, "tango-red-jet-set": 2.34, "camel-ponte-roma": 2.35,
    "ivory-rib-knit": 2.58, "11oz-black-denim": 2.72, "navy-sparkle-sweat": 3.00,
    "white-swim-solid": 3.11, "white-dots-on-blk": 3.45, "pink-ribbon-brown": 3.74,
    "royal-target": 3.87,
}


def test_the_ten_measured_fabrics_of_wang_2011_are_in_the_table():
    assert sorted(n.removeprefix("wang2011-") for n in WANG) == \
        sorted(REFERENCE_BENDING_LENGTH_CM)


@pytest.mark.parametrize("name", WANG)
def test_a_measured_row_is_in_the_published_ranges_and_names_its_file(name):
    p = load_presets()[name]
    assert not p.estimate
    assert f"materials/{name.removeprefix('wang2011-')}.json" in p.source
    # as stored: 113–324 g/m², bending 14–125 µN·m, stretching ~3 to ~2000 N/m
    assert 0.113 <= p.areal_density <= 0.324
    assert 14e-6 <= p.arcsim_bending <= 126e-6
    c11, _, c22, c33 = p.arcsim_stretching
    assert 3.0 <= min(c11, c22) <= max(c11, c22) <= 2100.0 and 10.0 <= c33 <= 110.0
    assert (p.stretch_warp, p.stretch_weft, p.shear, p.bending) == (
        2 * c11, 2 * c22, c33 / 2, p.arcsim_bending / 4)
    c_cm = 100 * math.cbrt(p.arcsim_bending / (p.areal_density * 9.81))
    assert c_cm == pytest.approx(REFERENCE_BENDING_LENGTH_CM[name.removeprefix("wang2011-")],
                                 abs=0.006)


def test_every_row_cites_a_source_and_an_estimate_says_how_it_was_made():
    presets = load_presets()
    assert {"cotton", "denim", "silk", "jersey", "leather"} <= set(presets)
    for p in presets.values():
        assert p.source.strip()
        if p.estimate:
            assert p.source == "estimate" and len(p.note) > 40
        else:
            assert "Wang" in p.source


def test_a_familiar_name_is_its_measured_row():
    denim, row = get_preset("denim"), get_preset("wang2011-11oz-black-denim")
    assert denim.alias_of == row.name
    assert (denim.areal_density, denim.stretch_warp, denim.stretch_weft, denim.shear,
            denim.bending) == (row.areal_density, row.stretch_warp, row.stretch_weft,
                               row.shear, row.bending)


GOOD_ROW = 'areal_density = 0.2\nstretch = 100\nshear = 10\nbending = 1e-5\nsource = "s"\n'


def test_a_table_of_the_same_form_parses():
    table = parse_presets(f"[a]\n{GOOD_ROW}\n[b]\nalias_of = \"a\"\n"
                          "[c]\nareal_density = 0.2\narcsim_stretching = [10, -3, 20, 8]\n"
                          "arcsim_bending = 4e-5\nsource = \"s\"\n")
    assert table["a"].stretch_warp == table["a"].stretch_weft == 100.0
    assert table["b"].bending == 1e-5 and table["b"].alias_of == "a"
    c = table["c"]
    assert (c.stretch_warp, c.stretch_weft, c.shear, c.bending) == (20.0, 40.0, 4.0, 1e-5)


@pytest.mark.parametrize("text, says", [
    ("[a\n", "not valid TOML"),
    (f"[a]\n{GOOD_ROW}colour = 1\n", "unknown key 'colour'"),
    ("[a]\nareal_density = 0.2\nstretch = 100\nshear = 10\nbending = 1e-5\n", "lacks source"),
    (f"[a]\n{GOOD_ROW}estimate = true\n", "must say in `note`"),
    ("[b]\nalias_of = \"nowhere\"\n", "not a row"),
    (GOOD_ROW.replace("0.2", "200.0").join(["[a]\n", ""]), "areal_density = 200.0"),
    (GOOD_ROW.replace("1e-5", "-1e-5").join(["[a]\n", ""]), "bending = -1e-05"),
    (GOOD_ROW.replace("100", "[100, 1, 2]").join(["[a]\n", ""]), "[warp, weft]"),
    (GOOD_ROW.replace("100", "nan").join(["[a]\n", ""]), "not a finite number"),
    (f"[a]\n{GOOD_ROW}arcsim_bending = 1e-5\n", "not both"),
    ("[a]\nareal_density = 0.2\narcsim_bending = 1e-5\nsource = \"s\"\n",
     "lacks arcsim_stretching"),
    ("[a]\nareal_density = 0.2\narcsim_stretching = [1, 2, 3]\narcsim_bending = 1e-5\n"
     "source = \"s\"\n", "four numbers"),
    ("[a]\nareal_density = 0.2\narcsim_stretching = [1, 0, 2, 3]\narcsim_bending = \"x\"\n"
     "source = \"s\"\n", "arcsim_bending = 'x' must be a number"),
])
def test_a_malformed_table_is_refused_in_one_line(text, says):
    with pytest.raises(MaterialError) as e:
        parse_presets(text, "mine.toml")
    assert says in str(e.value) and "mine.toml" in str(e.value)
    assert "\n" not in str(e.value)


def test_an_unknown_preset_lists_the_presets():
    with pytest.raises(MaterialError, match="not a preset; the presets are cotton, denim"):
        get_preset("velvet")
