"""scripts/quality_matrix.py's pictures: one metric against isotropic noise, one panel per mesh,
seeds averaged (matplotlib, Debian's python3-matplotlib)."""
import math

import matplotlib.pyplot as plt
from matplotlib.ticker import FuncFormatter, LogLocator, NullFormatter

from quality_matrix_report import RMSE_UNIT

# (label, where in a row, style): the noisy input, the best peer setting, fq's default.
SERIES = {
    "mfne": [("noisy input", lambda r: r["noisy"]["mfne"], dict(color="0.55", ls="--", marker="x")),
             ("best peer setting (lowest MFNE)", lambda r: r["best_peer"] and r["best_peer"]["mfne"],
              dict(color="tab:orange", marker="s")),
             ("fq default", lambda r: r["fq_default"]["mfne"], dict(color="tab:blue", marker="o", lw=2.2))],
    "rmse": [("noisy input", lambda r: r["noisy"]["rmse"], dict(color="0.55", ls="--", marker="x")),
             ("best peer setting (lowest MFNE)", lambda r: r["best_peer"] and r["best_peer"]["rmse"],
              dict(color="tab:orange", marker="s")),
             ("lowest RMSE of any peer setting", lambda r: r["lowest_peer_rmse"] and r["lowest_peer_rmse"]["rmse"],
              dict(color="tab:orange", ls=":", marker=".")),
             ("fq default", lambda r: r["fq_default"]["rmse"], dict(color="tab:blue", marker="o", lw=2.2))],
}
TITLES = {"mfne": "Mean face normal error (rad, log scale) against isotropic noise",
          "rmse": "Vertex RMSE (thousandths of the bounding-box diagonal, log scale) against isotropic noise"}


def _mean_by_level(rows, get):
    """{noise: mean over the seeds that have a value}."""
    sums = {}
    for r in rows:
        v = get(r)
        if v is not None:
            sums.setdefault(r["noise"], []).append(v)
    return {k: sum(v) / len(v) for k, v in sorted(sums.items())}


def _plain(y, _pos):
    return f"{y:g}"


def draw(doc, metric, path):
    rows = [r for r in doc["rows"] if r["direction"] == "iso"]
    meshes = list(dict.fromkeys(r["mesh"] for r in rows))
    if not meshes:
        return
    scale = 1 / RMSE_UNIT if metric == "rmse" else 1
    ncols = min(4, len(meshes))
    nrows = math.ceil(len(meshes) / ncols)
    fig, axes = plt.subplots(nrows, ncols, figsize=(3.8 * ncols, 3.1 * nrows + 1.0), squeeze=False)
    for ax, mesh in zip(axes.flat, meshes):
        mine = [r for r in rows if r["mesh"] == mesh]
        for label, get, style in SERIES[metric]:
            pts = _mean_by_level(mine, get)
            ax.plot(list(pts), [v * scale for v in pts.values()], label=label, ms=5, **style)
        ax.set_yscale("log")
        ax.yaxis.set_major_locator(LogLocator(subs=(1, 2, 5)))
        ax.yaxis.set_major_formatter(FuncFormatter(_plain))
        ax.yaxis.set_minor_formatter(NullFormatter())
        ax.set_xticks(sorted({r["noise"] for r in mine}))
        ax.xaxis.set_major_formatter(FuncFormatter(_plain))
        ax.tick_params(axis="x", labelsize=8, labelrotation=45)
        ax.grid(True, which="major", alpha=0.35)
        ax.set_title(f"{mesh} ({mine[0]['vertices']:,} V)", fontsize=10)
    for ax in axes.flat[len(meshes):]:
        ax.set_visible(False)
    for ax in axes[-1]:
        ax.set_xlabel("noise σ (mean edges)", fontsize=9)
    seeds = doc["meta"]["seeds"]
    seeds = f"mean of seeds {', '.join(map(str, seeds))}" if len(seeds) > 1 else f"seed {seeds[0]}"
    fig.suptitle(f"{TITLES[metric]}; {seeds}", fontsize=11)
    handles, labels = axes.flat[0].get_legend_handles_labels()
    fig.legend(handles, labels, loc="lower center", ncol=len(labels), frameon=False, fontsize=9)
    fig.tight_layout(rect=(0, 0.06 if nrows > 1 else 0.1, 1, 0.95))
    fig.savefig(path, dpi=110)
    plt.close(fig)
