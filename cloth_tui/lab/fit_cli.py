"""`cloth-tui lab fit --density G --bending-length C[,C] [--extension "E % at F N/W cm"]
[--drape DC [--drape-resolution N]] [--material BASE] [--solver NAME] [-o FILE.toml
[--scene SCENE]] [--json]`: the flags (on the lab's parser: this module imports nothing
heavy), their checks before any run, the file written and the report. fit.py fits and
proves."""

from __future__ import annotations

import json
import sys
from pathlib import Path

from ..usage import UsageError, check_output_path
from .strips import specimen_problem
from .study import LabError

FIT_FLAGS = {"density": "--density", "bending_length": "--bending-length",
             "extension": "--extension", "drape": "--drape",
             "drape_resolution": "--drape-resolution", "output": "--output",
             "scene": "--scene"}
HELP = "fit: a fabric from measurements, written as a [material] and proven by the lab"


def add_fit_arguments(parser) -> None:
    g = parser.add_argument_group(
        "lab fit", "a fabric from measurements: `lab fit --density G --bending-length C[,C]` "
                   "writes a [material] and runs the virtual Peirce (and drape) test on it; "
                   "--material names the preset that gives what was not measured (default "
                   "denim), --solver the solver of the proof")
    g.add_argument("--density", metavar="G/M²", help="areal density in g/m² (the label's)")
    g.add_argument("--bending-length", metavar="CM[,CM]",
                   help="bending length in cm (ASTM D1388: the overhang at the 41.5° line, "
                        "over two), one or warp,weft")
    g.add_argument("--extension", metavar="'E % at F N/W cm'",
                   help="a strip test's extension at a load, e.g. '5 %% at 10 N/5 cm' "
                        "('5,8 %% at …' for warp,weft): the stretch")
    g.add_argument("--drape", metavar="DC",
                   help="a Cusick drape coefficient (0–1, or 45 %%): the shear is fitted by "
                        "drape runs until the lab's drape test gives it")
    g.add_argument("--drape-resolution", metavar="N",
                   help="particles across the drape test's disc (default 25)")
    g.add_argument("-o", "--output", metavar="FILE.toml",
                   help="write the default scene (1 m hanging from two clips) with the "
                        "fabric as its [material]")
    g.add_argument("--scene", metavar="SCENE",
                   help="with -o: write this scene (file or built-in name) with the fabric "
                        "instead")


def refuse_fit_flags(args) -> None:
    """A lab test other than fit refuses fit's flags rather than ignore them."""
    given = [flag for key, flag in FIT_FLAGS.items() if getattr(args, key, None) is not None]
    if given:
        raise UsageError(f"{given[0]}: is for `cloth-tui lab fit`, not lab {args.test}")


def _say(notice):
    def say(text: str) -> None:
        notice.finish()
        print(f"lab fit: {text}", file=sys.stderr, flush=True)
    return say


def _inputs(args):
    """(measurements, solver, drape resolution, output path or None, scene or None), every
    flag checked before any run; a UsageError naming the flag."""
    from . import fit, study

    for flag, value in (("--resolutions", args.resolutions), ("--plot", args.plot)):
        if value is not None:
            raise UsageError(f"{flag}: is for the lab's tests; lab fit runs the Peirce test "
                             f"at {fit.PEIRCE_LINKS} links and the drape test at "
                             f"--drape-resolution")
    missing = [f for f, v in (("--density", args.density),
                              ("--bending-length", args.bending_length)) if v is None]
    if missing:
        raise UsageError(f"lab fit needs {' and '.join(missing)} (e.g. lab fit --density 250 "
                         f"--bending-length 2.4,1.9)")
    if args.drape_resolution is not None and args.drape is None:
        raise UsageError("--drape-resolution: is for --drape (the drape test's resolution)")
    if args.scene is not None and args.output is None:
        raise UsageError("--scene: needs -o FILE.toml, the scene file to write")
    try:
        m = fit.Measurements(
            areal_density=fit.parse_density(args.density),
            bending_lengths=fit.parse_bending_lengths(args.bending_length),
            stretch=fit.parse_extension(args.extension) if args.extension else None,
            drape=fit.parse_drape(args.drape) if args.drape is not None else None,
            base=args.material or fit.BASE_PRESET)
        study.lab_material(m.base)
        from .clamped import PEIRCE
        solver = study.check_solver(PEIRCE, args.solver)
        resolution = fit.DRAPE_RESOLUTION
        if args.drape_resolution is not None:
            from .drape import DRAPE
            (resolution,) = study.parse_resolutions(args.drape_resolution, DRAPE)
    except LabError as e:
        raise UsageError(str(e).replace("--resolutions", "--drape-resolution")) from None
    output = Path(args.output) if args.output is not None else None
    if output is not None:
        check_output_path(output, (".toml",))
    scene = None
    if output is not None:
        from ..scene_files import load
        # a SceneError is the user's: one line, exit 2
        scene = load(args.scene if args.scene is not None else "default")
    return m, solver, resolution, output, scene


def _check_specimens(material, m, solver, resolution) -> None:
    from . import fit
    from .clamped import PEIRCE
    from .drape import DRAPE

    problem = specimen_problem(PEIRCE, fit.PEIRCE_LINKS, material, solver)
    if problem:
        raise UsageError(f"--bending-length: the virtual Peirce test cannot run this fabric "
                         f"({problem})")
    if m.drape is not None:
        problem = specimen_problem(DRAPE, resolution, material, solver)
        if problem:
            raise UsageError(f"--drape: the drape test cannot run this fabric at {resolution} "
                             f"particles across ({problem})")


def file_text(table: dict, m, notes: list[str], scene=None) -> str:
    """The file: a comment naming the measurements and notes, then the [material] (alone, or
    in `scene`)."""
    from ..scene_files import dumps, toml_value

    said = [f"{m.areal_density * 1e3:g} g/m²", "bending length " + _lengths(m)]
    if m.stretch:
        said.append(f"stretch {m.stretch[0]:.4g} / {m.stretch[1]:.4g} N/m from the strip test")
    if m.drape is not None:
        said.append(f"drape coefficient {m.drape:g}")
    lines = ["# cloth-tui lab fit: a fabric from " + "; ".join(said)]
    lines += [f"# {n}" for n in notes]
    if scene is not None:
        return "\n".join(lines) + "\n" + dumps(scene)
    return "\n".join(lines + ["", "[material]"] +
                     [f"{k} = {toml_value(v)}" for k, v in table.items()]) + "\n"


def _lengths(m) -> str:
    if len(m.bending_lengths) == 2:
        return (f"warp {m.bending_lengths[0] * 100:g} cm, weft "
                f"{m.bending_lengths[1] * 100:g} cm")
    return f"{m.bending_lengths[0] * 100:g} cm"


def _write(path: Path, text: str) -> None:
    from ..util import atomic_write
    try:
        with atomic_write(path, "w", encoding="utf-8") as fh:
            fh.write(text)
    except OSError as e:
        raise UsageError(f"{path}: cannot write: {e.strerror or type(e).__name__}") from None


def _scene_with(scene, table: dict):
    """`scene` with the fabric as its [material]; a SceneError if its solver cannot take
    one."""
    from ..scene import from_dict, to_dict
    return from_dict(to_dict(scene) | {"material": table}, scene.name)


def run_fit(args) -> int:
    from ..compile_notice import CompileNotice
    from . import fit

    m, solver, resolution, output, scene = _inputs(args)
    try:
        table, notes = fit.closed_form(m)
    except LabError as e:
        raise UsageError(str(e)) from None
    if scene is not None:  # refused now, not after the runs
        from ..scene import SceneError
        try:
            _scene_with(scene, table)
        except SceneError as e:
            raise UsageError(f"--scene {args.scene}: {e}") from None
    _check_specimens(fit.material_of(table), m, solver, resolution)
    runs = []
    with CompileNotice(sys.stderr, sys.stderr.isatty()) as notice:
        say = _say(notice)
        try:
            if m.drape is not None:
                table, runs = fit.fit_drape(table, m.drape, resolution, solver, say)
                notes.append(f"shear fitted to the drape coefficient {m.drape:g} by {len(runs)} "
                             f"drape runs at {resolution} particles across ({solver})")
            text = file_text(table, m, notes,
                             _scene_with(scene, table) if scene is not None else None)
            material = fit.material_of(table)
            if output is not None:
                _write(output, text)
                say(f"written to {output}")
                from ..scene_files import load
                material = load(output).material.material  # the proof runs what was written
            proof = fit.prove(material, m, solver, resolution, say)
        except LabError as e:
            raise UsageError(str(e)) from None
    result = {"measured": {"areal_density": m.areal_density,
                           "bending_lengths": list(m.bending_lengths),
                           "stretch": list(m.stretch) if m.stretch else None,
                           "drape": m.drape, "base": m.base},
              "material": table, "notes": notes, "solver": solver, "drape_runs": runs,
              "proof": proof, "output": str(output) if output is not None else None}
    if args.json:
        print(json.dumps(result))
    else:
        print(format_fit(result, text if output is None else None))
    if not proof["ok"]:
        print("cloth-tui: lab fit: the fitted fabric does not pass its proof (see the report)",
              file=sys.stderr)
        return 1
    return 0


def format_fit(r: dict, section: str | None) -> str:
    """The report: what was measured, the material and where its values came from, and the
    proof against the bounds."""
    from . import fit

    mat, p = r["material"], r["proof"]
    bending = mat["bending"] if isinstance(mat["bending"], list) else [mat["bending"]]
    out = ["Textile lab · fit: a fabric from measurements.",
           (f"Material: {mat['areal_density'] * 1e3:g} g/m², stretch {mat['stretch'][0]:.4g} / "
            f"{mat['stretch'][1]:.4g} N/m, shear {mat['shear']:.4g} N/m, bending "
            f"{' / '.join(f'{b * 1e6:.4g}' for b in bending)} µN·m"
            f"{' (warp / weft)' if len(bending) == 2 else ''}.")]
    out += [f"Note: {n}." for n in r["notes"]]
    if section is not None:
        out += ["", section.rstrip()]
    out += ["", f"Proof ({r['solver']}), the lab's tests on the fabric as written:"]
    for pe in p["peirce"]:
        strip = f", strip along the {pe['direction']}" if len(p["peirce"]) == 2 else ""
        out.append(f"  virtual Peirce test ({fit.PEIRCE_LINKS} links{strip}): overhang "
                   f"{pe['overhang'] * 100:.4g} cm, bending length "
                   f"{pe['bending_length'] * 100:.4g} cm against {pe['expected'] * 100:.4g} "
                   f"cm: {pe['error']:+.2%}, within {pe['tolerance']:.0%}: "
                   f"{'yes' if pe['ok'] else 'NO'}")
    dr = p["drape"]
    if dr is not None:
        out.append(f"  drape test ({dr['resolution']} particles across): coefficient "
                   f"{dr['drape']:.3f} against {dr['expected']:.3f}: {dr['error']:+.3f}, "
                   f"within {dr['tolerance']:g}: {'yes' if dr['ok'] else 'NO'} "
                   f"({dr['folds']} folds)")
    if r["output"]:
        out += ["", f"written to {r['output']}"]
    return "\n".join(out)
