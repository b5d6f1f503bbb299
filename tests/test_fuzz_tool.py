"""tools/fuzz.py: its scenes are reproducible from the seed, reach every key of the schema,
write valid TOML, and its classification names the failures the issue lists."""

import dataclasses
import importlib.util
import tomllib
from pathlib import Path

from cloth_tui import scene as sc

spec = importlib.util.spec_from_file_location(
    "fuzz", Path(__file__).resolve().parent.parent / "tools" / "fuzz.py")
fuzz = importlib.util.module_from_spec(spec)
spec.loader.exec_module(fuzz)


def test_scenes_are_seeded_and_reach_every_key():
    assert fuzz.random_scene(3, 7) == fuzz.random_scene(3, 7)
    assert fuzz.random_scene(3, 7) != fuzz.random_scene(3, 8)
    seen, objects = set(), set()
    for i in range(120):
        doc = fuzz.random_scene(5, i)
        assert tomllib.loads(fuzz.to_toml(doc)) == doc
        for section, values in doc.items():
            if section == "objects":
                objects |= {k for o in values for k in o}
            elif section not in ("pins", "material"):
                seen |= {f"{section}.{k}" for k in values}
    assert seen == set(sc.all_keys())
    assert objects == {f.name for f in dataclasses.fields(sc.SceneObject)}


def test_scenes_carry_materials_pin_groups_cylinders_tori_and_sheets_at_rest():
    docs = [fuzz.random_scene(40, i) for i in range(200)]
    for doc in docs:
        assert tomllib.loads(fuzz.to_toml(doc)) == doc
    tables = [d["material"] for d in docs if isinstance(d.get("material"), dict)]
    assert any("preset" in t for t in tables) and any("preset" not in t for t in tables)
    assert any(fuzz.TINY in (t.get("shear"), t.get("tear_strength")) for t in tables)
    assert any(t.get("bending") == 0.0 for t in tables)  # its closed lower edge
    assert any(isinstance(t.get("stretch"), list) for t in tables)
    assert any(d.get("material") == "original" for d in docs)
    groups = [g for d in docs for g in d.get("pins", [])]
    assert any("keys" in g for g in groups) and any("offset" in g for g in groups)
    assert any(g.get("stiffness", 1.0) == 1.0 for g in groups)
    assert any(0 < g.get("stiffness", 1.0) < 1 for g in groups)
    shapes = {o.get("type") for d in docs for o in d.get("objects", [])}
    assert {"cylinder", "torus"} <= shapes
    rest = [d for d in docs if fuzz.at_rest(d)]
    assert len(rest) >= 10
    for doc in rest:
        assert doc["forces"]["gravity"] is False and not doc.get("objects")
    # --plain draws the scenes of the seeds recorded before these were added
    assert all("pins" not in fuzz.random_scene(40, i, plain=True) for i in range(50))


def test_most_scenes_are_valid_and_within_the_work_budget():
    valid = 0
    for i in range(100):
        doc = fuzz.random_scene(9, i)
        try:
            scene = sc.from_dict(doc)
        except sc.SceneError:
            continue
        valid += 1
        b = scene.behavior
        # the most substeps a frame may take: adaptive rises to max_substeps (pbd, xpbd)
        substeps = max(b.substeps, b.max_substeps) if b.adaptive and b.solver != "springs" \
            else b.substeps
        passes = b.iterations if b.solver != "springs" else \
            fuzz.IMPLICIT_PASSES if b.integrator in ("auto", "implicit_euler") else 4
        assert scene.cloth.resolution ** 2 * substeps * passes <= fuzz.WORK_BUDGET
    assert valid >= 50


def test_classification():
    doc = {"scene": {"thickness": 0.05}}
    good = ('{"finite": true, "penetration": 0.059, "halted": null}', "")
    assert fuzz.classify(0, *good, doc)[0] == ["ok"]
    assert fuzz.classify(0, good[0].replace("0.059", "0.061"), "", doc)[0] == ["penetration"]
    assert fuzz.classify(0, '{"finite": false, "penetration": 0, "halted": "x"}',
                         "RuntimeWarning: overflow\n", doc)[0] == ["non_finite", "halted",
                                                                  "stderr", "runtime_warning"]
    assert fuzz.classify(2, "", "cloth-tui: error: x\n", doc)[0] == ["refused"]
    assert fuzz.classify(2, "", "Traceback\n  x\n", doc)[0] == ["bad_message", "traceback"]
    assert fuzz.classify(1, "", "cloth-tui: internal error\n", doc)[0] == ["exit_1"]
    assert fuzz.classify(None, "", "", doc)[0] == ["timeout"]
    assert fuzz.classify(2, "", "Traceback (most recent call last):\n", doc)[0] == \
        ["refused", "traceback"]
    # the compile notice is not a warning, on a success or around a refusal
    notice = ("cloth-tui: compiling kernels (first run only)…\n"
              "cloth-tui: 3 kernels compiled in 12 s; later runs load them from numba's cache\n")
    assert fuzz.classify(0, *good[:1], notice, doc)[0] == ["ok"]
    assert fuzz.classify(2, "", notice + "cloth-tui: error: x\n", doc)[0] == ["refused"]


def test_a_sheet_that_starts_inside_the_floor_is_not_a_penetration():
    # seed 40, scene 3: a sheet 798 m under the floor reported its start as its penetration
    doc = {"cloth": {"height": -5.0, "pinned": "none", "resolution": 4},
           "scene": {"floor_height": -0.5, "thickness": 0.005}}
    assert abs(fuzz.start_depth(doc) - 4.5) < 1e-9
    out = '{"finite": true, "penetration": %g, "halted": null}'
    assert fuzz.classify(0, out % 5.7, "", doc)[0] == ["started_inside"]
    above = {**doc, "cloth": {**doc["cloth"], "height": 0.25}}
    assert fuzz.start_depth(above) == 0.0
    assert fuzz.classify(0, out % 5.7, "", above)[0] == ["penetration"]


def test_json_must_be_valid_and_finite_must_vouch_for_every_number():
    doc = {}
    nan = '{"finite": true, "penetration": 0, "energy": NaN, "min_y": 0}'
    assert fuzz.classify(0, nan, "", doc)[0] == ["bad_json"]  # json.loads alone accepts NaN
    null = ('{"finite": true, "penetration": 0, "min_y": null, "max_speed": 0, '
            '"max_stretch": 0, "mean_stretch": 0}')
    assert fuzz.classify(0, null, "", doc)[0] == ["false_finite"]
    assert fuzz.classify(0, null.replace("true", "false"), "", doc)[0] == ["non_finite"]
    assert fuzz.classify(0, null.replace("null", "0.1"), "", doc)[0] == ["ok"]


def test_one_scene_runs_in_its_own_process():
    result = fuzz.run_one(seed=1, index=7, frames=2, timeout=120, keep=None)
    assert result["exit"] in (0, 2) and result["classes"]


def test_a_halt_is_a_failure_unless_the_step_is_past_the_stability_limit():
    halted = '{"finite": true, "penetration": 0, "halted": "the step diverges"}'
    # rk4 springs at 2000 N/m on 0.3 mg particles: 0.66·√(m/k) = 0.26 ms, 16 × 1 substep at
    # 31.6 frames/s is 2 ms: a true divergence
    explicit = {"behavior": {"solver": "springs", "integrator": "rk4", "substeps": 1,
                             "frame_rate": 31.58}}
    assert fuzz.classify(0, halted, "", explicit)[0] == ["diverged"]
    explicit["behavior"]["substeps"] = 64  # 15 µs: stable, so a halt is not explained
    assert fuzz.classify(0, halted, "", explicit)[0] == ["halted"]
    assert fuzz.classify(0, halted, "", {})[0] == ["halted"]  # pbd never diverges while finite
    # a sheet nothing moves must never halt, whatever its integrator's stability limit
    rest = {**explicit, "forces": {"gravity": False, "wind": False, "rain": False,
                                   "custom": "none"},
            "behavior": {**explicit["behavior"], "substeps": 1, "wave": False},
            "scene": {"object": "none", "moving": False}}
    assert fuzz.at_rest(rest)
    assert fuzz.classify(0, halted, "", rest)[0] == ["halted_at_rest"]
