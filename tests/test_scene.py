import pytest

from cloth_tui import scene as sc
from cloth_tui import scene_files as sf
from cloth_tui.resources import builtin_scenes
from cloth_tui.scene import Scene, SceneError
from cloth_tui.scene_reference import reference_markdown


def test_defaults_keep_the_originals_proportions():
    s = Scene()
    assert s.cloth.size == 1.0 and s.cloth.resolution == 26 and s.cloth.pinned == "corners"
    assert s.behavior.damping == 0.03 and s.behavior.solver == "hpbd"
    assert s.behavior.integrator == "auto"
    assert sc.integrator_for(s.behavior) == "verlet"
    assert sc.integrator_for(s.with_value("behavior.solver", "springs").behavior) \
        == "implicit_euler"
    assert s.forces.gravity_strength == 9.81


def test_builtin_default_is_addressable_by_name():
    assert "default" in builtin_scenes()
    assert sf.load("default").cloth.resolution == 33


def test_builtin_original_is_the_schema_defaults():
    """The original's sheet, which the defaults of every key describe."""
    assert sf.load("original") == Scene()


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
    ("[[objects]]\ntype = \"teapot\"\n", ["objects[0].type", "sphere"]),
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


def test_the_renamed_tolerance_key_still_loads_as_the_error_tolerance(tmp_path):
    # behavior.stretch_tolerance bounded the stretch; for pbd that is the solve error the
    # tolerance now bounds, so old files and overrides mean what they meant
    path = tmp_path / "old.toml"
    path.write_text("[behavior]\nstretch_tolerance = 0.02\n", encoding="utf-8")
    assert sf.load(path).behavior.error_tolerance == 0.02
    s = sf.apply_overrides(Scene(), ["behavior.stretch_tolerance=0.03"])
    assert s.behavior.error_tolerance == 0.03
    assert "error_tolerance = 0.03" in sf.dumps(s) and "stretch_tolerance" not in sf.dumps(s)
    with pytest.raises(SceneError, match="error_tolerance"):
        sf.apply_overrides(Scene(), ["behavior.stretch_tolerance=0"])


def test_with_value_leaves_original_untouched():
    s = Scene()
    with pytest.raises(SceneError):
        s.with_value("cloth.size", -3)
    assert s.cloth.size == 1.0


def test_the_docs_document_every_key():
    from pathlib import Path
    page = (Path(__file__).parent.parent / "docs" / "scene-keys.md").read_text(encoding="utf-8")
    assert reference_markdown() in page, ("docs/scene-keys.md's key reference is stale: "
                                          "regenerate it with python tools/scene_keys_page.py")


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


# -- rectangular sheets ---------------------------------------------------------------------
@pytest.mark.parametrize("size, resolution, shape", [
    (1.0, 26, (26, 26)),                 # a square, as before
    ([2.0, 1.0], 26, (26, 14)),          # 26 along the longer x, 14 along z: 1/13 m apart
    ([1.0, 0.1], 41, (41, 5)),           # the strip: 0.025 m both ways
    ([0.1, 1.0], 41, (5, 41)),           # the same strip along z
    ([1.0, 0.3], 11, (11, 4)),           # 0.1 m along x; 4 rows give 0.1 m exactly
    ([1.0, 0.34], 11, (11, 4)),          # 0.113 m is nearer 0.1 than 0.085 m (5 rows)
    ([1.0, 0.36], 11, (11, 5)),          # 0.09 m is nearer 0.1 than 0.12 m (4 rows)
    (1.0, [7, 13], (7, 13)),             # given counts: spacings 1/6 m and 1/12 m
    ([3.0, 1.0], [31, 11], (31, 11)),
])
def test_grid_shape_of_each_form(size, resolution, shape):
    s = Scene().with_values({"cloth.size": size, "cloth.resolution": resolution})
    assert s.cloth.grid_shape() == shape
    width, length = (size, size) if isinstance(size, float) else size
    assert s.cloth.dimensions() == (width, length)


def test_an_integer_resolution_spaces_the_shorter_side_nearest_to_the_longer():
    for length in (0.05, 0.13, 0.27, 0.5, 0.61, 0.99):
        s = Scene().with_values({"cloth.size": [1.0, length], "cloth.resolution": 21})
        nx, nz = s.cloth.grid_shape()
        assert nx == 21
        want = 1.0 / 20
        best = min(range(2, 30), key=lambda k: abs(length / (k - 1) - want))
        assert nz == best, length


def test_pairs_load_save_and_override_round_trip(tmp_path):
    s = sf.apply_overrides(Scene(), ["cloth.size=[2, 0.5]", "cloth.resolution=[30, 9]"])
    assert s.cloth.size == [2.0, 0.5] and s.cloth.resolution == [30, 9]
    assert isinstance(s.cloth.resolution[0], int)
    back = sf.load(sf.save(s, tmp_path / "banner.toml"))
    assert back == s and back.cloth.grid_shape() == (30, 9)
    assert "size = [2.0, 0.5]" in (tmp_path / "banner.toml").read_text()


@pytest.mark.parametrize("key, value, words", [
    ("cloth.size", [1.0], ["cloth.size", "two entries", "[width, length]"]),
    ("cloth.size", [1.0, 2.0, 3.0], ["cloth.size", "two entries"]),
    ("cloth.size", [1.0, float("nan")], ["cloth.size", "finite"]),
    ("cloth.size", [1.0, float("inf")], ["cloth.size", "finite"]),
    ("cloth.size", [0.0, 1.0], ["cloth.size", "0.01 ≤"]),
    ("cloth.size", [1.0, -1.0], ["cloth.size", "0.01 ≤"]),
    ("cloth.size", [1.0, "wide"], ["cloth.size", "'wide'"]),
    ("cloth.size", [1.0, True], ["cloth.size"]),
    ("cloth.resolution", [7], ["cloth.resolution", "[nx, nz]"]),
    ("cloth.resolution", [7, 1], ["cloth.resolution", "2 ≤"]),
    ("cloth.resolution", [7, 513], ["cloth.resolution", "≤ 512"]),
    ("cloth.resolution", [7, 2.5], ["cloth.resolution", "integer"]),
    ("cloth.resolution", [[7, 8], 9], ["cloth.resolution"]),
])
def test_bad_pairs_are_one_line_errors(key, value, words):
    s = Scene()
    with pytest.raises(SceneError) as e:
        s.with_value(key, value)
    assert "\n" not in str(e.value)
    for w in words:
        assert w in str(e.value)
    assert s.cloth.size == 1.0 and s.cloth.resolution == 26  # left untouched


def test_a_sheet_so_thin_it_has_one_row_is_refused():
    # 1 m × 1 cm at 26 along x: 4 cm apart, so the width holds a quarter of a spacing.
    with pytest.raises(SceneError) as e:
        sf.loads("[cloth]\nsize = [1.0, 0.01]\nresolution = 26\n")
    assert "single row" in str(e.value) and "1 particle along z" in str(e.value)
    assert "\n" not in str(e.value)
    s = sf.loads("[cloth]\nsize = [1.0, 0.01]\nresolution = [26, 2]\n")  # counts given: fine
    assert s.cloth.grid_shape() == (26, 2)
    with pytest.raises(SceneError, match="single column"):
        sf.loads("[cloth]\nsize = [0.01, 1.0]\nresolution = 26\n")


def test_naive_self_collision_is_bounded_by_particles_on_any_shape():
    Scene().with_values({"behavior.self_collision": "naive", "cloth.resolution": [256, 64]})
    with pytest.raises(SceneError, match="naive"):
        Scene().with_values({"behavior.self_collision": "naive",
                             "cloth.resolution": [256, 65]})


def test_square_scenes_keep_their_numbers_and_forms():
    # Files written before the pair forms load to the same values they always had; the
    # scenes written for rectangular sheets use the pairs.
    rectangular = {"banner", "strip"}
    for name in rectangular:
        assert isinstance(sf.load(name).cloth.size, list)
    for name in set(builtin_scenes()) - rectangular:
        s = sf.load(name)
        assert isinstance(s.cloth.size, float) and isinstance(s.cloth.resolution, int)
        n = s.cloth.resolution
        assert s.cloth.grid_shape() == (n, n)
        assert s.cloth.dimensions() == (s.cloth.size, s.cloth.size)
