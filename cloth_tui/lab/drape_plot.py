"""`lab drape --plot`: the drape as the Cusick meter's lamp shows it, from above. One row per
fabric: its shadow at each resolution (the support disc, the flat specimen's circle, the
draped outline filled), each to scale with equal axes, and beside them the drape
coefficient against resolution on its whole range, 0 to 1, with the folds written at each
point."""

from __future__ import annotations

from pathlib import Path

from .drape import SPECIMEN_RADIUS, SUPPORT_RADIUS

SHADOW = "#2b5d8a"


def plot_drape(r: dict, path: Path) -> None:
    """Writes drape_figure(r) to the PNG `path`."""
    import matplotlib.pyplot as plt

    from ..util import atomic_write

    fig = drape_figure(r)
    with atomic_write(Path(path)) as fh:
        fig.savefig(fh, format="png")
    plt.close(fig)


def drape_figure(r: dict):
    """The figure of a drape study's result `r` (study.run's dict)."""
    import matplotlib
    matplotlib.use("Agg")
    import matplotlib.pyplot as plt

    cases = r["cases"]
    ns = sorted({p["resolution"] for c in cases for p in c["points"]})
    cols = len(ns) + 1
    fig, axes = plt.subplots(len(cases), cols, figsize=(2.6 * cols + 0.8, 2.7 * len(cases)),
                             dpi=110, squeeze=False)
    for row, case in zip(axes, cases):
        by_n = {p["resolution"]: p for p in case["points"]}
        for ax, n in zip(row[:-1], ns):
            _shadow(ax, by_n.get(n))
            ax.set_title(f"N = {n}" + (f": DC {by_n[n]['measured']:.3f}, "
                                       f"{by_n[n].get('folds', '?')} folds"
                                       if n in by_n else ""), fontsize=8)
        row[0].set_ylabel(case["label"].split(":")[0], fontsize=9)
        _coefficient(row[-1], case, ns)
    material = f" · {r['material']['preset']}" if r["material"] else ""
    fig.suptitle(f"cloth-tui lab drape{material} · {r['solver']} · from above: support "
                 f"{SUPPORT_RADIUS * 200:g} cm (grey), flat specimen {SPECIMEN_RADIUS * 200:g}"
                 f" cm (dashed), shadow (blue)", fontsize=9)
    fig.tight_layout()
    return fig


def _shadow(ax, point: dict | None) -> None:
    """The shadow of one run to scale, in cm from the support's middle: its outline (the
    hem, projected) filled by the nonzero rule, so a fold lying over its neighbour still
    reads as shadow."""
    from matplotlib.patches import Circle, Polygon

    lim = SPECIMEN_RADIUS * 100 * 1.08
    ax.set_xlim(-lim, lim)
    ax.set_ylim(-lim, lim)
    ax.set_aspect("equal")
    ax.tick_params(labelsize=6)
    ax.add_patch(Circle((0, 0), SPECIMEN_RADIUS * 100, fill=False, ls="--", lw=0.8,
                        color="0.35"))
    if point and point.get("outline"):
        outline = [(x * 100, z * 100) for x, z in point["outline"]]
        ax.add_patch(Polygon(outline, closed=True, facecolor=SHADOW, alpha=0.55,
                             edgecolor=SHADOW, lw=0.8))
    ax.add_patch(Circle((0, 0), SUPPORT_RADIUS * 100, color="0.55", alpha=0.9))
    ax.set_xlabel("cm", fontsize=6)


def _coefficient(ax, case: dict, ns: list[int]) -> None:
    pts = sorted(case["points"], key=lambda p: p["resolution"])
    xs = [p["resolution"] for p in pts]
    ax.plot(xs, [p["measured"] for p in pts], "o-", color=SHADOW)
    for p in pts:
        ax.annotate(f"{p.get('folds', '?')} folds", (p["resolution"], p["measured"]),
                    textcoords="offset points", xytext=(0, 7), ha="center", fontsize=6)
    ax.set_ylim(0, 1)
    ax.set_xticks(ns, [str(n) for n in ns])
    if len(ns) == 1:
        ax.set_xlim(ns[0] - 10, ns[0] + 10)
    else:
        pad = 0.08 * (ns[-1] - ns[0])
        ax.set_xlim(ns[0] - pad, ns[-1] + pad)
    ax.grid(True, alpha=0.25)
    ax.tick_params(labelsize=6)
    ax.set_xlabel("N (particles across)", fontsize=7)
    ax.set_title("drape coefficient", fontsize=8)
