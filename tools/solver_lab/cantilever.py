"""The lab's clamped strip (cloth_tui/lab/clamped.py) at the default scene's solver, substeps,
iterations and accuracy control, or with other behaviour keys: its settled tip drop against
the heavy elastica, or why it did not settle.

    python tools/solver_lab/cantilever.py [--loads 2,8,20] [--links 10,20,40] [key=value ...]

e.g. `iterations=8 adaptive=false substeps=20` (TOML values) for the lab's own settings with lbfgs.
docs/physics.md (lbfgs, "Where the solve starts") has what this printed.
"""

from __future__ import annotations

import argparse
import time

from cloth_tui.lab import clamped
from cloth_tui.lab.elastica import cantilever
from cloth_tui.lab.study import LabError, lab_material
from cloth_tui.scene_files import load, parse_override
from cloth_tui.scene_keys import SceneError


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--loads", default="2,8,20", help="wL³/B, comma-separated")
    parser.add_argument("--links", default="10,20,40", help="free links, comma-separated")
    parser.add_argument("--material", default="denim")
    parser.add_argument("keys", nargs="*", help="behaviour key=value over the default's")
    args = parser.parse_args()
    default = load("default").behavior
    behavior = {key: getattr(default, key) for key in
                ("solver", "substeps", "iterations", "adaptive", "error_tolerance")}
    for pair in args.keys:
        try:
            key, value = parse_override(f"behavior.{pair}")
        except SceneError as e:
            parser.error(str(e))
        behavior[key.removeprefix("behavior.")] = value
    material = lab_material(args.material)
    print(f"{args.material}, behaviour {behavior}")
    for load_ratio in (float(v) for v in args.loads.split(",")):
        length = clamped.strip_for_load(load_ratio, material)
        want = cantilever(load_ratio).tip_drop
        for links in (int(v) for v in args.links.split(",")):
            start = time.perf_counter()
            try:
                r = clamped.settle_clamped(length, links, material, behavior=behavior)
                told = (f"{r['drop'] / length / want - 1:+.2%} of the elastica's tip drop, "
                        f"settled at {r['settled_s']:.1f} s")
            except LabError as e:
                told = str(e)
            print(f"wL³/B = {load_ratio:g}, {links} links: {told} "
                  f"({time.perf_counter() - start:.1f} s wall)", flush=True)


if __name__ == "__main__":
    main()
