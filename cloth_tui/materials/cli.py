"""`cloth-tui materials [--json]`: the fabric presets ([material] preset = "NAME") with their
values in SI units and where their numbers come from. Text: a table in the units a textile
lab reads (g/m², N/m, µN·m), then each preset's source; --json: one object in SI base units
with the unit of every value. Pure Python."""

from __future__ import annotations

import json

from .catalogue import preset_rows
from .presets import Preset

# JSON's values are in these units; the table shows g/m² and µN·m
UNITS = {"areal_density": "kg/m²", "stretch_warp": "N/m", "stretch_weft": "N/m",
         "stretch_warp_strained": "N/m", "stretch_weft_strained": "N/m", "shear": "N/m",
         "bending": "N·m", "bending_45": "N·m", "bending_90": "N·m", "tear_strength": "N/m",
         "strain_of_strained": "1"}


def preset_record(p: Preset, kind: str, short: str) -> dict:
    """One preset as JSON: SI values (UNITS), the stiffened stretch and the bending by
    direction where it was measured (else null), and its source."""
    curves, folds = p.stretch_curves, p.bending_by_direction
    return {"name": p.name, "kind": kind, "alias_of": p.alias_of or None,
            "estimate": p.estimate, "areal_density": p.areal_density,
            "stretch_warp": p.stretch_warp, "stretch_weft": p.stretch_weft,
            "stretch_warp_strained": curves[0].high if curves else None,
            "stretch_weft_strained": curves[1].high if curves else None,
            "strain_of_strained": curves[0].reach if curves else None,
            "shear": p.shear, "bending": p.bending,
            "bending_45": folds.fold_45 if folds else None,
            "bending_90": folds.fold_90 if folds else None,
            "tear_strength": p.tear_strength, "source": p.source, "source_short": short,
            "note": p.note or None}


def _g(v: float) -> str:
    return f"{v:.3g}"


def format_table(records: list[dict]) -> str:
    head = ["preset", "fabric", "g/m²", "stretch N/m warp, weft", "shear N/m",
            "bending µN·m 0°, 45°, 90°", "tears N/m", "source"]
    rows = []
    for r in records:
        bending = [r["bending"]] + [r[k] for k in ("bending_45", "bending_90") if r[k]]
        name = r["name"] + (f" = {r['alias_of']}" if r["alias_of"] else "")
        rows.append([name, r["kind"], f"{1e3 * r['areal_density']:.4g}",
                     f"{_g(r['stretch_warp'])}, {_g(r['stretch_weft'])}", _g(r["shear"]),
                     ", ".join(_g(1e6 * b) for b in bending),
                     _g(r["tear_strength"]) if r["tear_strength"] is not None else "–",
                     r["source_short"]])
    widths = [max(len(h), *(len(row[i]) for row in rows)) for i, h in enumerate(head)]
    line = lambda cells: "  ".join(c.ljust(w) for c, w in zip(cells, widths)).rstrip()  # noqa: E731
    out = [line(head)] + [line(row) for row in rows]
    out += ["", "Measured knits and wovens stiffen with strain and bend differently by "
                "direction: `--json` gives the stretch at the strained sample and each "
                "direction's rigidity.", "", "Sources:"]
    for r in records:
        if r["alias_of"]:
            continue
        source = r["source"] + (f": {r['note']}" if r["estimate"] and r["note"] else "")
        out.append(f"  {r['name']}: {source}")
    return "\n".join(out)


def run_materials(args) -> int:
    records = [preset_record(row.preset, row.kind, row.source) for row in preset_rows()]
    if args.json:
        print(json.dumps({"units": UNITS, "presets": records}))
    else:
        print(format_table(records))
    return 0
