import pytest

from cloth_tui import scene as sc
from cloth_tui import scene_files as sf
from cloth_tui.resources import builtin_scenes
from cloth_tui.scene import Scene, SceneError
from cloth_tui.scene_reference import reference_markdown


def test_defaults_keep_the_originals_proportions():
    s = Scene()
    assert s.cloth.size == 1.0 and s.cloth.resolution == 26 and s.cloth.pinned == "corners"
    assert s.behavior.damping == 0.03 and s.behavior.solver == "pbd"
    assert s.behavior.integrator == "auto"
    assert sc.integrator_for(s.behavior) == "verlet"
    assert sc.integrator_for(s.with_value("behavior.solver", "springs").behavior) \
        == "implicit_euler"
    assert s.forces.gravity_strength == 9.81


def test_builtin_default_is_addressable_by_name():
    assert "default" in builtin_scenes()
    assert sf.load("default").cloth.resolution == 26


def test_save_and_load_round_trip(tmp_path):
    s = Scene().with_value("forces.wind", True).with_value("cloth.resolution", 40)
    s.objects.append(sc.SceneObject(type="box", center=[0.1, 0.0, 0.0]))
    s.objects.append(sc.SceneObject(type="capsule", axis=[0.0, 0.0, 1.0], length=0.3))
    path = sf.save(s, tmp_path / "mine.toml")
    back = sf.load(path)
    assert back == s


@pytest.mark.parametrize("text, words", [
    ("[cloth\n", ["syntax"]),
    ("[cloth]\nbogus = 1\n", ["cloth.bogus", "size"]),
    ("[cloth]\nsize = \"big\"\n", ["cloth.size", "'big'", "number"]),
    ("[cloth]\nresolution = 1\n", ["cloth.resolution", "2"]),
    ("[behavior]\ndamping = 1.0\n", ["behavior.damping", "< 1"]),
    ("[forces]\nwind_direction = [0, 0, 0]\n", ["wind_direction", "zero"]),
    ("[nope]\n", ["[nope]"]),
    ("[[objects]]\ntype = \"torus\"\n", ["objects[0].type", "sphere"]),
    ("[appearance]\ncloth_color = \"red\"\n", ["cloth_color", "#rrggbb"]),
    ("[behavior]\nsolver = \"pbd\"\nintegrator = \"rk4\"\n", ["integrator", "springs"]),
    # capsules used to reuse a plane's `normal` and a box's size[1] for axis and length
    ("[[objects]]\ntype = \"capsule\"\nsize = [0.0, 0.5, 0.0]\nnormal = [1.0, 0.0, 0.0]\n",
     ["objects[0]", "capsule", "axis", "length"]),
    ("[[objects]]\ntype = \"capsule\"\nnormal = [0.0, 0.0, 1.0]\n", ["axis", "length"]),
])
def test_bad_documents_name_the_problem(text, words):
    with pytest.raises(SceneError) as e:
        sf.loads(text)
    msg = str(e.value)
    assert "\n" not in msg
    for w in words:
        assert w in msg


def test_overrides_parse_toml_values_and_bare_strings():
    s = sf.apply_overrides(Scene(), ["forces.wind=true", "cloth.pinned=one_edge",
                                     "forces.wind_direction=[1, 0, 0]", "cloth.size=2"])
    assert s.forces.wind is True and s.cloth.pinned == "one_edge"
    assert s.forces.wind_direction == [1.0, 0.0, 0.0] and s.cloth.size == 2.0


@pytest.mark.parametrize("bad", ["nokey", "cloth.size", "cloth.size=", "x.y=1", "cloth.nope=1",
                                 "cloth.size=nan", "cloth.resolution=2.5"])
def test_malformed_overrides_raise_scene_error(bad):
    with pytest.raises(SceneError):
        sf.apply_overrides(Scene(), [bad])


def test_with_value_leaves_original_untouched():
    s = Scene()
    with pytest.raises(SceneError):
        s.with_value("cloth.size", -3)
    assert s.cloth.size == 1.0


def test_readme_documents_every_key():
    from pathlib import Path
    readme = (Path(__file__).parent.parent / "README.md").read_text(encoding="utf-8")
    assert reference_markdown() in readme, ("README key reference is stale: regenerate it from "
                                            "cloth_tui.scene_reference.reference_markdown()")


def test_overrides_that_constrain_each_other_apply_in_any_order():
    # (no floor: a 15 m wave's trough would hold the edge inside it, which is refused)
    a = sf.apply_overrides(Scene(), ["scene.floor=false", "behavior.wave=true",
                                     "behavior.wave_amplitude=15", "behavior.wave_frequency=0.5"])
    assert a.behavior.wave_amplitude == 15.0
    with pytest.raises(SceneError, match="max_speed"):
        sf.apply_overrides(Scene(), ["behavior.wave=true", "behavior.wave_amplitude=15"])


def test_with_objects_replaces_and_validates_the_objects():
    base = Scene().with_value("forces.wind", True)
    new = base.with_objects([{"type": "box", "size": [0.2, 0.2, 0.2]}, {"type": "sphere"}])
    assert [o.type for o in new.objects] == ["box", "sphere"] and new.forces.wind
    assert base.objects == []  # a copy
    with pytest.raises(SceneError, match=r"objects\[0\]: a mesh needs `path`"):
        base.with_objects([{"type": "mesh"}])
    with pytest.raises(SceneError, match=r"objects\[1\]\.radius"):
        base.with_objects([{"type": "sphere"}, {"type": "sphere", "radius": -1.0}])
