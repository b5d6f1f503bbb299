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
            else:
                seen |= {f"{section}.{k}" for k in values}
    assert seen == set(sc.all_keys())
    assert objects == {f.name for f in dataclasses.fields(sc.SceneObject)}


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
                                                                  "stderr"]
    assert fuzz.classify(2, "", "cloth-tui: error: x\n", doc)[0] == ["refused"]
    assert fuzz.classify(2, "", "Traceback\n  x\n", doc)[0] == ["bad_message"]
    assert fuzz.classify(1, "", "cloth-tui: internal error\n", doc)[0] == ["exit_1"]
    assert fuzz.classify(None, "", "", doc)[0] == ["timeout"]


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
