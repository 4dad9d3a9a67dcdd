"""The figures of ``ndlfd reproduce``: one matplotlib figure per paper figure.

Each ``draw_fig*`` function takes the results of the matching experiment of
:mod:`ndlfd.jobs._reproduction_runs` (the ``line`` runs) and returns a
:class:`matplotlib.figure.Figure`; :func:`ndlfd.jobs.reproduction.reproduce`
saves them.
"""

from __future__ import annotations

import numpy as np

from .._errors import MissingExtraError
from ..demonstration import Demonstration
from ..plot import plot_demos, plot_path
from ._reproduction_runs import CHANNELS, NORMALIZATION_MODES

__all__ = ["draw_fig2", "draw_fig3", "draw_fig5", "draw_fig6"]


# --------------------------------------------------------------- figures
def _figure(n_rows: int, n_cols: int, size=(4.2, 3.8)):
    try:
        from matplotlib.figure import Figure
    except ImportError:  # pragma: no cover - depends on the environment
        raise MissingExtraError(
            "ndlfd reproduce draws figures with matplotlib; install it with:"
            ' pip install "ndlfd[plot]"'
        ) from None
    return Figure(figsize=(size[0] * n_cols, size[1] * n_rows), layout="constrained")


def draw_fig2(results: dict):
    fig = _figure(1, 3, size=(4.6, 4.4))
    titles = {
        "none": "(a) no normalization",
        "per-dimension": "(b) per-dimension",
        "group": "(c) by group",
    }
    for i, mode in enumerate(NORMALIZATION_MODES):
        r = results[mode]
        ax = fig.add_subplot(1, 3, i + 1, projection="3d")
        plot_path(ax, r["values"], keypoints=r["keypoints"], lw=1.0)
        ax.set_box_aspect(tuple(np.maximum(r["ranges"], 1e-9)))
        prop = ":".join(f"{p:.2g}" for p in r["proportions"])
        ax.set_title(f"{titles[mode]}\n{r['n_keypoints']} key points, X:Y:Z = {prop}")
        ax.set_xlabel("X")
        ax.set_ylabel("Y")
        ax.set_zlabel("Z")
    fig.suptitle("Fig. 2 analogue: 6-D spiral (position + velocity), key points")
    return fig


def draw_fig3(demo: Demonstration, results: dict, epsilon: float):
    fig = _figure(1, 3)
    P = demo.get("position")
    labels = {
        "position": "(a) position only",
        "velocity": "(b) velocity only",
        "both": "(c) position + velocity",
    }
    for i, name in enumerate(CHANNELS):
        ax = fig.add_subplot(1, 3, i + 1)
        r = results[name]
        plot_path(ax, P, lw=1.0)
        K = P[r["keypoints"]]
        ax.plot(K[:, 0], K[:, 1], "o", color="#d62728", markersize=4)
        ax.set_aspect("equal", adjustable="datalim")
        ax.set_title(f"{labels[name]}: {r['n_keypoints']} key points")
        ax.set_xlabel(demo.select("position").columns[0])
        ax.set_ylabel(demo.select("position").columns[1])
    fig.suptitle(
        f"Fig. 3 analogue: 2-D curve with variable velocity, one tolerance"
        f" ε = {epsilon:g} (key points in red, on the position path)"
    )
    return fig


def draw_fig5(shape: str, train, test, results: dict, results_paper: dict):
    dims = test.get("position").shape[1]
    proj = {"projection": "3d"} if dims == 3 else {}
    fig = _figure(2, 4)
    low, high = f"{dims}-D", f"{2 * dims}-D"
    sample = list(train[:6])
    for row, name in enumerate(("position", "position+velocity")):
        r = results[name]
        tag = low if name == "position" else high
        ax = fig.add_subplot(2, 4, 4 * row + 1, **proj)
        plot_demos(
            sample[:2],
            keypoints=r["model"].keypoints_[:2],
            ax=ax,
            title=(
                f"key points of 2 demos, {tag} ({name})\n"
                f"all {len(train)}: {r['min']}–{r['max']} per demo"
            ),
            max_demos=None,
        )
        ax = fig.add_subplot(2, 4, 4 * row + 2, **proj)
        plot_demos(
            sample,
            generated=r["generated"],
            ax=ax,
            title=f"training sample and generated path, {tag}",
            max_demos=None,
        )
        ax = fig.add_subplot(2, 4, 4 * row + 3, **proj)
        e = r["errors"]
        plot_demos(
            [],
            generated=r["generated"],
            test=test,
            ax=ax,
            title=(
                f"test vs generated, {tag}\ndifference {e['difference_pct']:.2f} %,"
                f" Fréchet {e['frechet']:.2f}"
            ),
        )
    ax = fig.add_subplot(2, 4, 4)
    counts = {}
    for dist, res in (("line", results), ("paper", results_paper)):
        counts[f"{low}\n{dist}"] = res["position"]["counts"]
        counts[f"{high}\n{dist}"] = res["position+velocity"]["counts"]
    names = list(counts)
    ax.boxplot([counts[k] for k in names], tick_labels=names)
    ax.set_ylabel("key points per training demonstration")
    ax.set_title(f"key-point counts, {len(train)} demonstrations")
    ax = fig.add_subplot(2, 4, 8)
    bars = {
        f"generated\n{low}": results["position"]["errors"]["difference_pct"],
        f"generated\n{high}": results["position+velocity"]["errors"]["difference_pct"],
        "mean-demo\nbaseline": results["baseline"]["errors"]["difference_pct"],
        "typical\ndemo": results["demos_median"],
    }
    ax.bar(
        range(len(bars)),
        list(bars.values()),
        color=["#d62728", "#9467bd", "#7f7f7f", "#7fa7d6"],
    )
    ax.set_xticks(range(len(bars)), list(bars), fontsize="small")
    ax.set_ylabel("difference % to the test demonstration")
    ax.set_title("difference to the test")
    fig.suptitle(f"Fig. 5 analogue: {shape}, {low} vs {high} (line distance)")
    return fig


def draw_fig6(test, results: dict):
    levels = list(results["paths"])
    fig = _figure(1, len(levels))
    for i, lv in enumerate(levels):
        ax = fig.add_subplot(1, len(levels), i + 1)
        e = results["errors"][lv]
        lo, hi = results["ranges"][lv]
        for edge in np.linspace(lo, hi, lv + 1):
            ax.axvline(edge, color="#cccccc", lw=0.5, zorder=0)
            ax.axhline(edge, color="#cccccc", lw=0.5, zorder=0)
        plot_demos(
            [],
            generated=results["keys"][lv],
            test=test,
            ax=ax,
            title=f"{lv} levels: difference to test {e['difference_pct']:.2f} %",
        )
    d = ", ".join(f"{k}: {v:.2f} %" for k, v in results["differences"].items())
    fig.suptitle(
        f"Fig. 6 analogue: codebook resolution (2-D square, grey: level edges);"
        f" differences between generated paths {d}"
    )
    return fig
