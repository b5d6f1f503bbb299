"""The scene's [material] section: files, overrides, round trips and clear refusals."""

import pytest

from cloth_tui.materials.presets import get_preset
from cloth_tui.materials.schema import strip_rigidities
from cloth_tui.scene import Scene, SceneError
from cloth_tui.scene_files import apply_overrides, dumps, loads

XPBD = '[behavior]\nsolver = "xpbd"\n'


def test_a_preset_with_an_override_gives_the_preset_and_the_override():
    s = loads('[material]\npreset = "denim"\ndamping = 0.5\n' + XPBD)
    m, p = s.material.material, get_preset("denim")
    assert (m.areal_density, m.stretch_warp, m.stretch_weft, m.bending) == \
        (p.areal_density, p.stretch_warp, p.stretch_weft, p.bending)
    assert m.damping == 0.5 and s.material.name == "denim"


def test_no_section_and_original_are_the_same_scene():
    assert loads("").material is None
    assert loads('material = "original"') == loads("")
    assert loads('[material]\npreset = "original"') == loads("")


def test_a_scene_saved_says_what_its_author_wrote_and_loads_back_equal():
    s = loads('[material]\npreset = "silk"\nstretch = [300, 200]\n' + XPBD)
    text = dumps(s)
    assert '[material]\npreset = "silk"\nstretch = [300, 200]\n' in text
    assert loads(text) == s


def test_overrides_change_one_key_and_a_new_preset_keeps_the_keys_given_beside_it():
    s = loads('[material]\npreset = "denim"\ndamping = 0.5\n' + XPBD)
    silk = apply_overrides(s, ["material.preset=silk"])
    assert silk.material.table == {"preset": "silk", "damping": 0.5}
    assert silk.material.material.areal_density == get_preset("silk").areal_density
    assert apply_overrides(s, ["material=original"]).material is None
    assert apply_overrides(s, ["material.preset=original"]).material is None
    fresh = apply_overrides(Scene(), ["behavior.solver=xpbd", "material.preset=knit"])
    assert fresh.material.material.preset == "knit"
    # the default solver (hpbd) takes a material as it is
    assert apply_overrides(Scene(), ["material.preset=knit"]).behavior.solver == "hpbd"


@pytest.mark.parametrize("text, words", [
    ('[material]\npreset = "denimx"\n' + XPBD, "not a preset"),
    ('[material]\npreset = "denim"\n[behavior]\nsolver = "pbd"\n',
     'needs behavior.solver = "hpbd" or "xpbd"'),
    ('material = "denim"', 'material = "original" or a [material] table'),
    ('material = 3', "must be a table"),
    ('[material]\nstretch = 3\n' + XPBD, "missing: areal_density, shear, bending"),
    ('[material]\npreset = "denim"\nbending = -1\n' + XPBD, "material.bending = -1"),
    ('[material]\npreset = "denim"\nwarp = 1\n' + XPBD, "unknown key material.warp"),
    ('[material]\npreset = "original"\ndamping = 1\n', "takes no other [material] keys"),
])
def test_bad_sections_are_refused_in_one_line_naming_the_key(text, words):
    with pytest.raises(SceneError) as e:
        loads(text)
    assert words in str(e.value) and "\n" not in str(e.value)


def test_a_refused_override_leaves_the_scene_as_it_was():
    s = loads('[material]\npreset = "denim"\n' + XPBD)
    with pytest.raises(SceneError, match="unknown key 'material.colour'"):
        apply_overrides(s, ["material.colour=1"])
    with pytest.raises(SceneError, match='needs behavior.solver = "hpbd" or "xpbd"'):
        s.with_value("behavior.solver", "pbd")
    assert s.material.material.preset == "denim" and s.behavior.solver == "xpbd"


def test_bending_by_direction_is_a_warp_weft_pair_in_a_file_and_an_override():
    s = loads('[material]\npreset = "silk"\nbending = [3e-5, 1.5e-5]\n' + XPBD)
    m = s.material.material
    assert strip_rigidities(m) == (3e-5, 1.5e-5)
    assert m.bending == 1.5e-5   # a fold along the warp, as a measured preset's `bending`
    assert '[material]\npreset = "silk"\nbending = [3e-05, 1.5e-05]\n' in dumps(s)
    assert loads(dumps(s)) == s
    over = apply_overrides(s, ["material.bending=[2e-5, 4e-5]"])
    assert strip_rigidities(over.material.material) == (2e-5, 4e-5)
    one = apply_overrides(s, ["material.bending=2e-5"])   # one number: isotropic again
    assert one.material.material.bending_by_direction is None


@pytest.mark.parametrize("value, words", [
    ("[3e-5]", "a list must be [warp, weft]"),
    ("[3e-5, 1e-5, 2e-5]", "a list must be [warp, weft]"),
    ("[3e-5, 0]", "needs both positive (bending = 0 for none)"),
    ("[3e-5, -1]", "material.bending = -1 is not allowed"),
    ('[3e-5, "stiff"]', "material.bending = 'stiff' is not allowed"),
    ("[20, 1e-5]", "material.bending = 20 is not allowed"),
])
def test_a_bad_bending_pair_is_refused_in_one_line(value, words):
    with pytest.raises(SceneError) as e:
        loads(f'[material]\npreset = "denim"\nbending = {value}\n' + XPBD)
    assert words in str(e.value) and "\n" not in str(e.value)
    assert "[warp, weft]" in str(e.value)   # what is expected, said
    with pytest.raises(SceneError) as e:
        apply_overrides(loads('[material]\npreset = "denim"\n' + XPBD),
                        [f"material.bending={value}"])
    assert words in str(e.value)
