"""Seeded scene fuzzer: N random scenes over every key of the schema, each simulated by
`python -m cloth_tui simulate` in its own process with a timeout.

    python tools/fuzz.py --count 300 --seed 1 --jobs 2 [--frames 120] [--keep DIR]
    python tools/fuzz.py --seed 1 --only 17 --keep DIR     # regenerate one scene to debug

Each run is classified:
  ok            exit 0, finite, penetration ≤ thickness + 1 cm, not halted, stderr empty
  refused       exit 2 with one line on stderr (the scene is bad input; that is fine)
  exit_N        any other exit status (1 = a crash: a bug)
  bad_message   exit 2 but the message is not one line
  timeout       no result within --timeout seconds
  non_finite    exit 0 but positions are not finite
  penetration   deepest contact penetration beyond scene.thickness + 1 cm
  started_inside  that penetration, where the flat sheet starts inside the floor or an
                object: the measure counts the start and its first substep (not judged)
  halted        the guard gave up (divergence even at 16× the substeps), in a scene that
                should be stable: a failure
  diverged      the guard gave up on springs with an explicit integrator whose substep is
                beyond the documented stability limit even at 16× (a true divergence: fine)
  stderr        exit 0 with output on stderr (warnings)
A run can have several classes; the summary counts each. `--keep DIR` writes the TOML of
every run that is not ok or refused, named by its index, to reproduce with `simulate`.

Values are drawn from each key's declaration (range, choices, kind): the declared edges,
the default, and log-uniform values between, plus an occasional value outside the range or
of the wrong type (to exercise refusal). So that each run ends in seconds on a shared
machine, the work of a frame (particles × substeps × passes, counting the substeps adaptive
may rise to and implicit Euler's solver iterations: `work_per_frame`) is kept under a budget
by lowering iterations, then max_substeps, then substeps, then resolution; every key still
reaches its extremes alone. A run that still exceeds --timeout is a failure ("timeout").
"""

from __future__ import annotations

import argparse
import dataclasses
import json
import math
import os
import random
import re
import subprocess
import sys
import tempfile
import time
from concurrent.futures import ThreadPoolExecutor
from pathlib import Path

ROOT = Path(__file__).resolve().parent.parent
sys.path.insert(0, str(ROOT))

from cloth_tui import scene as sc  # noqa: E402  (the repository's own package, not installed)
from cloth_tui.materials.presets import preset_names
from cloth_tui.materials.values import KEYS as MATERIAL_KEYS
from cloth_tui.resources import assets_dir  # noqa: E402
from cloth_tui.sim.run.runner import MAX_GUARD_LEVEL  # noqa: E402

WORK_BUDGET = 1_000_000  # particles × substeps × passes per frame (work_per_frame)
IMPLICIT_PASSES = 40  # what a substep of implicit Euler is counted as (see _passes)
PENETRATION_SLACK = 0.01  # m beyond scene.thickness
WRONG = ["text", True, -1, 1e308, [1, 2], {"a": 1}, float("inf")]
TINY = 5e-324  # the smallest positive float: an open lower bound of 0 accepts it
SOFT = [1e-9, 0.01, 0.5, 0.9, 0.99, 0.9999, 0.999999]  # soft pin stiffnesses (hard is 1)
# What `finite: true` vouches for and that a measured run always has (others may be null)
ALWAYS_NUMBERS = ("min_y", "max_speed", "max_stretch", "mean_stretch", "penetration")
# The compile notice is news, not a warning: a cold cache prints it on any run
NOTICE = re.compile(r"cloth-tui: (compiling kernels|\d+ kernels compiled in)")


def _number(rng: random.Random, f: dataclasses.Field) -> float | int:
    m = f.metadata
    lo = -1e3 if m["lo"] is None else m["lo"]
    hi = 1e3 if m["hi"] is None else m["hi"]
    default = f.default
    pick = rng.random()
    if pick < 0.15:
        v = lo
    elif pick < 0.3:
        v = hi
    elif pick < 0.45:
        v = default
    elif lo < 0 < hi and rng.random() < 0.7:  # heights: mostly near the sheet and floor
        v = rng.uniform(max(lo, -3.0), min(hi, 3.0))
    elif lo > 0 or (lo == 0 and rng.random() < 0.7):  # log-uniform over positive ranges
        lo_pos = max(lo, 1e-9, hi * 1e-12)
        v = math.exp(rng.uniform(math.log(lo_pos), math.log(hi)))
    else:
        v = rng.uniform(lo, hi)
    if sc.value_type(f) == "int":
        v = int(round(v))
    elif m["lo_open"] and v == lo:
        v = lo + abs(lo) * 1e-9 + 1e-12
    if m["hi_open"] and v == hi:
        v = hi - abs(hi) * 1e-9
    return v


def _vector(rng: random.Random, f: dataclasses.Field, name: str) -> list[float]:
    scale = rng.choice([0.1, 0.5, 1.0, 1.0, 2.0, 10.0, 1e6]) if name != "size" else \
        rng.choice([0.01, 0.2, 0.5, 1.0, 3.0])
    v = [rng.uniform(-scale, scale) for _ in range(3)]
    if name == "size":
        v = [abs(x) for x in v]
    if rng.random() < 0.1:  # an axis-aligned or nearly degenerate direction
        v = [0.0, 0.0, 0.0]
        v[rng.randrange(3)] = rng.choice([1.0, -1.0, 1e-5, sc.MIN_DIRECTION_NORM])
    return v


def random_value(rng: random.Random, f: dataclasses.Field):
    m = f.metadata
    if m["choices"]:
        return rng.choice(m["choices"])
    if m["kind"] == "color":
        return "#%06x" % rng.randrange(1 << 24)
    if m["kind"] == "texture":
        return rng.choice(["none", "none", "maze", "grass"])
    if m["kind"].startswith("vec3"):
        return _vector(rng, f, f.name)
    if f.type in ("bool", bool):
        return rng.random() < 0.5
    return _number(rng, f)


def random_scene(seed: int, index: int, budget: int = WORK_BUDGET, plain: bool = False) -> dict:
    """Scene `index` of run `seed`: each key set with probability 1/2; unless `plain`, a
    [material], [[pins]] groups, cylinders and tori, or a sheet at rest, drawn from a stream
    of their own (so the other keys are those a plain scene of the seed has)."""
    rng = random.Random(seed * 1_000_003 + index)
    doc: dict = {}
    for section in sc.SECTIONS:
        values = {f.name: random_value(rng, f)
                  for f in dataclasses.fields(sc.SECTION_TYPES[section]) if rng.random() < 0.5}
        if values:
            doc[section] = values
    if rng.random() < 0.4:
        doc["objects"] = [{f.name: random_value(rng, f) for f in dataclasses.fields(sc.SceneObject)
                           if rng.random() < 0.6 and f.name != "path"}
                          for _ in range(rng.randint(1, 3))]
        for obj in doc["objects"]:  # a mesh needs a file, and only a mesh takes one
            if obj.get("type") == "mesh":
                obj["path"] = str(assets_dir() / "meshes" / "torus.ply")
    if rng.random() < 0.1:  # one value of the wrong type or out of range: must be refused
        section = rng.choice(sc.SECTIONS)
        name = rng.choice([f.name for f in dataclasses.fields(sc.SECTION_TYPES[section])])
        doc.setdefault(section, {})[name] = rng.choice(WRONG)
    behavior = doc.get("behavior", {})
    if behavior.get("solver", "pbd") != "springs" and rng.random() < 0.9:
        behavior.pop("integrator", None)  # pbd/xpbd need verlet: keep most scenes runnable
    if not plain:
        _extras(random.Random(f"extras-{seed}-{index}"), doc)
    _sheet_above_floor(rng, doc)
    _within_budget(doc, budget)
    return {k: v for k, v in doc.items() if v}


def _extras(rng: random.Random, doc: dict) -> None:
    """A [material] (half the scenes), [[pins]] groups (a third), cylinders and tori among the
    objects; one scene in eight is a sheet at rest instead."""
    if rng.random() < 0.125:
        _at_rest(rng, doc)
        return
    if rng.random() < 0.5:
        doc["material"] = random_material(rng)
        behavior = doc.get("behavior", {})  # a material needs hpbd, xpbd or lbfgs: mostly so
        if behavior.get("solver") in ("pbd", "springs") and rng.random() < 0.7:
            behavior.pop("solver")
            behavior.pop("integrator", None)
    if rng.random() < 0.35:
        doc["pins"] = [random_pin_group(rng, k) for k in range(rng.randint(1, 3))]
        if rng.random() < 0.8:  # the pattern would hold the corners differently: refused
            doc.setdefault("cloth", {})["pinned"] = "none"
    for obj in doc.get("objects", []):
        if rng.random() < 0.5:
            obj["type"] = rng.choice(["cylinder", "torus"])
            obj.pop("path", None)
            if obj["type"] == "torus" and rng.random() < 0.8:  # mostly a tube inside its ring
                obj["major_radius"] = rng.choice([0.05, 0.3, 1.0])
                obj["minor_radius"] = obj["major_radius"] * rng.choice([0.02, 0.1, 0.5, 0.99])


def random_material(rng: random.Random) -> dict | str:
    """A preset (with some keys over it), or every key typed: the edges of each range (the
    smallest float above an open 0), log-uniform between; sometimes a value to refuse."""
    if rng.random() < 0.05:
        return "original"
    preset = rng.random() < 0.5
    table: dict = {"preset": rng.choice(preset_names())} if preset else {}
    for name, spec in MATERIAL_KEYS.items():
        needed = name in ("areal_density", "stretch", "shear", "bending")
        if rng.random() < (0.7 if preset else 0.0 if needed else 0.5):
            continue
        table[name] = _material_number(rng, spec)
        if name == "stretch" and rng.random() < 0.3:
            table[name] = [table[name], _material_number(rng, spec)]
    if rng.random() < 0.05:
        table[rng.choice(list(MATERIAL_KEYS) + ["colour"])] = rng.choice(WRONG)
    return table


def _material_number(rng: random.Random, spec) -> float:
    lo_pos = TINY if spec.lo_open else 0.0
    return rng.choice([lo_pos, lo_pos, spec.hi, 1e-300, 1e-12,
                       math.exp(rng.uniform(math.log(1e-9), math.log(spec.hi)))])


def random_pin_group(rng: random.Random, k: int, still: bool = False) -> dict:
    """Group k: rows and columns (negative from the end) or single particles in row k or
    k from the end (so that groups seldom hold a particle two ways, which is refused), held
    hard, softly or along keys; `still`: held where they are."""
    g: dict = {}
    row = rng.choice([k, -1 - k])
    if rng.random() < 0.3:
        g["at"] = [[k, rng.choice([0, 1, 2])] for _ in range(rng.randint(1, 3))]
    else:
        if rng.random() < 0.8:
            g["rows"] = [row, row]
        if rng.random() < 0.6:
            g["cols"] = rng.choice([[0, 0], [-1, -1], [0, -1], [1, -2]])
    if rng.random() < 0.5:
        g["stiffness"] = rng.choice(SOFT)
    if still:
        return g
    scale = rng.choice([0.0, 0.05, 0.5, 3.0, 1e3])
    if rng.random() < 0.4:
        t, keys = 0.0, []
        for _ in range(rng.randint(1, 4)):
            keys.append([t] + [rng.uniform(-scale, scale) for _ in range(3)])
            t += rng.choice([1e-6, 0.01, 0.1, 1.0])
        g["keys"] = keys
    elif rng.random() < 0.7:
        g["offset"] = [rng.uniform(-scale, scale) for _ in range(3)]
    return g


def _at_rest(rng: random.Random, doc: dict) -> None:
    """Nothing moves the sheet: no gravity, wind, rain, custom force, wave, objects or moving
    pins (any solver, integrator, material and pins held where they are)."""
    doc["forces"] = {k: v for k, v in doc.get("forces", {}).items()
                     if k in ("integrate", "gravity_strength", "wind_strength")}
    doc["forces"].update(gravity=False, wind=False, rain=False, custom="none")
    doc.setdefault("behavior", {})["wave"] = False
    doc.setdefault("scene", {}).update(object="none", moving=False)
    doc.pop("objects", None)
    if rng.random() < 0.5:
        doc["material"] = random_material(rng)
    if rng.random() < 0.3:
        doc["pins"] = [random_pin_group(rng, k, still=True) for k in range(rng.randint(1, 2))]
        doc.setdefault("cloth", {})["pinned"] = "none"


def at_rest(doc: dict) -> bool:
    """Whether nothing in the scene moves its sheet (see _at_rest)."""
    forces, scene = doc.get("forces", {}), doc.get("scene", {})
    return (forces.get("gravity") is False and forces.get("wind") is False
            and forces.get("rain") is False and forces.get("custom") == "none"
            and doc.get("behavior", {}).get("wave") is False and not doc.get("objects")
            and scene.get("object") == "none" and scene.get("moving") is False
            and not any("keys" in g or "offset" in g for g in doc.get("pins", [])))


def _sheet_above_floor(rng: random.Random, doc: dict) -> None:
    """Most of the time, swap a sheet height and floor height drawn the wrong way round:
    pinned sheets starting inside the floor are refused, and half the scenes would be."""
    cloth, section = doc.get("cloth", {}), doc.get("scene", {})
    h, f = cloth.get("height", 0.25), section.get("floor_height", -0.5)
    numbers = all(isinstance(v, (int, float)) and not isinstance(v, bool) for v in (h, f))
    if numbers and h < f and rng.random() < 0.8:
        doc.setdefault("cloth", {})["height"], doc.setdefault("scene", {})["floor_height"] = f, h


def _passes(behavior: dict, iterations: int) -> int:
    """Sweeps over the particles per substep: the constraint passes of pbd/xpbd, the conjugate
    gradient iterations of implicit Euler (typically tens at its tolerance, up to 400), the
    stages of an explicit integrator (rk4 has four)."""
    if behavior.get("solver", "pbd") != "springs":
        return iterations
    return IMPLICIT_PASSES if behavior.get("integrator", "auto") in ("auto", "implicit_euler") \
        else 4


def work_per_frame(doc: dict) -> int | None:
    """Particles × substeps × passes of the scene's most expensive frame without a guard
    retry: with adaptive (pbd, xpbd), the substeps may rise to max_substeps. None if a value
    is of the wrong type (the scene will be refused)."""
    cloth, behavior = doc.get("cloth", {}), doc.get("behavior", {})
    get = {"resolution": cloth.get("resolution", 26), "substeps": behavior.get("substeps", 4),
           "iterations": behavior.get("iterations", 4),
           "max_substeps": behavior.get("max_substeps", 128)}
    if not all(isinstance(v, int) and not isinstance(v, bool) and v > 0 for v in get.values()):
        return None
    return get["resolution"] ** 2 * _substeps(behavior, get["substeps"], get["max_substeps"]) \
        * _passes(behavior, get["iterations"])


def _substeps(behavior: dict, substeps: int, max_substeps: int) -> int:
    adaptive = behavior.get("adaptive", True) and behavior.get("solver", "pbd") != "springs"
    return max(substeps, max_substeps) if adaptive is True else substeps


def _within_budget(doc: dict, budget: int = WORK_BUDGET) -> None:
    """Lower iterations, then the adaptive ceiling, then substeps, then the resolution until
    work_per_frame is within `budget`."""
    if work_per_frame(doc) is None:
        return
    cloth, behavior = doc.setdefault("cloth", {}), doc.setdefault("behavior", {})
    if behavior.get("self_collision") == "naive":
        cloth["resolution"] = min(cloth.get("resolution", 26), 32)
    while work_per_frame(doc) > budget:
        it, ms = behavior.get("iterations", 4), behavior.get("max_substeps", 128)
        s = behavior.get("substeps", 4)
        adaptive = _substeps(behavior, s, ms) > s
        if it > 4 and behavior.get("solver", "pbd") != "springs":
            behavior["iterations"] = max(4, it // 2)
        elif adaptive and ms > 4:
            behavior["max_substeps"] = max(4, ms // 2)
        elif s > 4:
            behavior["substeps"] = max(4, s // 2)
        else:
            cloth["resolution"] = max(2, int(cloth.get("resolution", 26) / 1.5))


def to_toml(doc: dict) -> str:
    def value(v) -> str:
        if isinstance(v, bool):
            return "true" if v else "false"
        if isinstance(v, float):
            return {math.inf: "inf", -math.inf: "-inf"}.get(v, repr(v))
        if isinstance(v, (int, float)):
            return repr(v)
        if isinstance(v, str):
            return json.dumps(v)
        if isinstance(v, list):
            return "[" + ", ".join(value(x) for x in v) + "]"
        if isinstance(v, dict):
            return "{" + ", ".join(f"{k} = {value(x)}" for k, x in v.items()) + "}"
        raise TypeError(type(v))

    # top-level keys (material = "original") before the first table, which would own them
    lines = [f"{k} = {value(v)}" for k, v in doc.items() if not isinstance(v, (dict, list))]
    for section, values in doc.items():
        if section in ("objects", "pins"):
            for obj in values:
                lines += [f"[[{section}]]"] + [f"{k} = {value(v)}" for k, v in obj.items()]
        elif not isinstance(values, dict):
            continue
        elif values:
            lines += [f"[{section}]"] + [f"{k} = {value(v)}" for k, v in values.items()]
    return "\n".join(lines) + "\n"


def _no_constant(name: str):
    raise ValueError(f"{name} is not JSON")


def classify(code: int | None, out: str, err: str, doc: dict) -> tuple[list[str], dict]:
    if code is None:
        return ["timeout"], {}
    err = "".join(line for line in err.splitlines(keepends=True) if not NOTICE.match(line))
    alarms = (["traceback"] if "Traceback" in err else []) + \
        (["runtime_warning"] if "RuntimeWarning" in err else [])
    if code == 2:
        return (["refused"] if err.count("\n") == 1 and err.endswith("\n") else
                ["bad_message"]) + alarms, {}
    if code != 0:
        return [f"exit_{code}"] + alarms, {}
    try:  # NaN and Infinity are Python's extensions, not JSON
        stats = json.loads(out, parse_constant=_no_constant)
    except ValueError:
        return ["bad_json"] + alarms, {}
    classes = []
    if not stats["finite"]:
        classes.append("non_finite")
    elif any(k in stats and not isinstance(stats[k], (int, float)) for k in ALWAYS_NUMBERS):
        classes.append("false_finite")  # a number written as null, yet `finite` vouched
    thickness = doc.get("scene", {}).get("thickness", sc.SceneSection().thickness)
    depth = stats.get("penetration") or 0.0
    if depth > thickness + PENETRATION_SLACK:
        classes.append("started_inside" if start_depth(doc) > 0 else "penetration")
    if stats.get("halted"):
        classes.append("halted_at_rest" if at_rest(doc) else
                       "diverged" if unstable_even_at_the_guards_substeps(doc) else "halted")
    if err.strip():
        classes.append("stderr")
    return classes + alarms or ["ok"], stats


def start_depth(doc: dict) -> float:
    """How deep the flat sheet starts inside the floor or an object (its true surface; 0 if
    outside them all), m. `penetration` then counts the start and the first substep's move
    before the push out (a sheet 798 m under the floor reports 799 m), the scene's doing."""
    import numpy as np

    from cloth_tui.sim.collision.colliders import build_colliders
    from cloth_tui.sim.model import build_model

    scene = sc.from_dict(doc)
    behavior = dataclasses.replace(scene.behavior, tethers=False)
    model = build_model(scene.cloth, behavior, scene.pins)
    x = model.rest_positions
    return max([0.0] + [float(np.max(-c.signed_distance(x)))
                        for c in build_colliders(scene, model)])


def unstable_even_at_the_guards_substeps(doc: dict) -> bool:
    """Springs with an explicit integrator whose substep, even at the guard's most substeps,
    is beyond the stability limit the stiffness key documents, h < 0.66·√(m/k) (m the
    lightest particle's mass): a divergence, which the guard is right to halt."""
    scene = sc.from_dict(doc)
    b, c = scene.behavior, scene.cloth
    if b.solver != "springs" or sc.integrator_for(b) == "implicit_euler":
        return False
    nx, nz = c.grid_shape()
    lightest = c.mass / (nx * nz) if c.mass_model == "uniform" else \
        c.mass / ((nx - 1) * (nz - 1)) / 4
    h = 1.0 / (b.frame_rate * b.substeps * 2 ** MAX_GUARD_LEVEL)
    return h > 0.66 * math.sqrt(lightest / b.stiffness)


def run_one(seed: int, index: int, frames: int, timeout: float, keep: Path | None,
            budget: int = WORK_BUDGET, plain: bool = False) -> dict:
    doc = random_scene(seed, index, budget, plain)
    text = to_toml(doc)
    with tempfile.TemporaryDirectory(prefix="cloth-fuzz-") as tmp:
        path = Path(tmp) / f"fuzz-{seed}-{index}.toml"
        path.write_text(text, encoding="utf-8")
        env = dict(os.environ, PYTHONPATH=str(ROOT) + os.pathsep + os.environ.get("PYTHONPATH", ""))
        t0 = time.monotonic()
        try:
            proc = subprocess.run([sys.executable, "-m", "cloth_tui", "simulate", str(path),
                                   "--frames", str(frames), "--json"], capture_output=True,
                                  text=True, timeout=timeout, env=env, cwd=tmp)
            code, out, err = proc.returncode, proc.stdout, proc.stderr
        except subprocess.TimeoutExpired:
            code, out, err = None, "", ""
        seconds = time.monotonic() - t0
    classes, stats = classify(code, out, err, doc)
    if keep is not None and not set(classes) <= {"ok", "refused"}:
        keep.mkdir(parents=True, exist_ok=True)
        (keep / f"fuzz-{seed}-{index}.toml").write_text(text, encoding="utf-8")
    return {"index": index, "classes": classes, "exit": code, "seconds": round(seconds, 1),
            "stderr": err.strip().splitlines()[-1][:300] if err.strip() else "",
            "penetration": stats.get("penetration"), "halted": stats.get("halted"),
            "recoveries": stats.get("recoveries")}


def main(argv: list[str] | None = None) -> int:
    p = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    p.add_argument("--count", type=int, default=20, help="scenes to run")
    p.add_argument("--seed", type=int, default=1)
    p.add_argument("--only", type=int, help="run only scene INDEX of this seed")
    p.add_argument("--jobs", type=int, default=2, help="processes at once")
    p.add_argument("--frames", type=int, default=120)
    p.add_argument("--timeout", type=float, default=180.0, help="seconds per scene")
    p.add_argument("--keep", type=Path, help="write the TOML of each failing scene here")
    p.add_argument("--json", action="store_true", help="one JSON object per scene on stdout")
    p.add_argument("--budget", type=int, default=WORK_BUDGET,
                   help="most particles × substeps × passes a frame may take")
    p.add_argument("--plain", action="store_true",
                   help="no [material], [[pins]], forced cylinders and tori or sheets at rest "
                        "(the scenes the seed 1 and 23 results were drawn from)")
    p.add_argument("--start", type=int, default=0, help="first scene index (to run in chunks)")
    args = p.parse_args(argv)
    indices = [args.only] if args.only is not None else \
        list(range(args.start, args.start + args.count))
    counts: dict[str, int] = {}
    failures = []
    with ThreadPoolExecutor(max_workers=max(1, args.jobs)) as pool:
        results = pool.map(lambda i: run_one(args.seed, i, args.frames, args.timeout,
                                             args.keep, args.budget, args.plain), indices)
        for r in results:
            for c in r["classes"]:
                counts[c] = counts.get(c, 0) + 1
            if not set(r["classes"]) <= {"ok", "refused", "diverged", "started_inside"}:
                failures.append(r)
            print(json.dumps(r) if args.json else
                  f"{r['index']:5d} {','.join(r['classes']):<24} {r['seconds']:6.1f}s "
                  f"{r['stderr'][:100]}", flush=True)
    print(f"seed {args.seed}, {len(indices)} scenes, {args.frames} frames: " +
          ", ".join(f"{k} {v}" for k, v in sorted(counts.items())), file=sys.stderr)
    return 1 if failures else 0


if __name__ == "__main__":
    sys.exit(main())
