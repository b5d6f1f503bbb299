"""The lab's clamped strip (cloth_tui/lab/clamped.py) at the default scene's solver, substeps,
iterations and accuracy control, or with other behaviour keys: its settled tip drop against
the heavy elastica, or why it did not settle.

    python tools/solver_lab/cantilever.py [--loads 2,8,20] [--links 10,20,40] [key=value ...]

e.g. `iterations=8 adaptive=false substeps=20` (TOML values) for the lab's own settings with lbfgs.
docs/physics.md (lbfgs, "Where the solve starts") has what this printed.
"""

from __future__ import annotations

import argparse
import math
import time

from cloth_tui.lab import clamped
from cloth_tui.lab.elastica import cantilever
from cloth_tui.lab.study import LabError, lab_material
from cloth_tui.scene_files import load, parse_override
from cloth_tui.scene_keys import SceneError


def _numbers(kind):
    """An argparse type: comma-separated numbers of `kind`, each positive and finite."""
    def parse(text: str) -> list:
        try:
            values = [kind(v) for v in text.split(",")]
        except ValueError:
            raise argparse.ArgumentTypeError(f"{text!r}: expected numbers such as 2,8,20")
        if not all(0 < v < math.inf for v in values):
            raise argparse.ArgumentTypeError(f"{text!r}: every number must be positive "
                                             "and finite")
        return values
    return parse


def main() -> None:
    parser = argparse.ArgumentParser(
        description="The lab's clamped strip at the default scene's behaviour (or the keys "
                    "given): its settled tip drop against the heavy elastica.")
    parser.add_argument("--loads", type=_numbers(float), default=[2.0, 8.0, 20.0],
                        help="wL³/B, comma-separated (default 2,8,20)")
    parser.add_argument("--links", type=_numbers(int), default=[10, 20, 40],
                        help="free links, comma-separated (default 10,20,40)")
    parser.add_argument("--material", default="denim", help="a preset (default denim)")
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
    try:
        material = lab_material(args.material)
    except LabError as e:
        parser.error(str(e))
    print(f"{args.material}, behaviour {behavior}")
    for load_ratio in args.loads:
        length = clamped.strip_for_load(load_ratio, material)
        want = cantilever(load_ratio).tip_drop
        for links in args.links:
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
