"""The evaluation report's figures (used by :mod:`ndlfd.jobs.evaluation`).

* :func:`boxplot_figure`: DTW/range per generator, one panel per group and
  protocol;
* :func:`shape_figure`: one shape's first fold, one panel per protocol (the via
  point and the observed prefix marked) and, when the reference generator
  samples, a panel of its samples as thin lines.
"""

from __future__ import annotations

import numpy as np

from .. import plot
from ..demonstration import Demonstration
from ._evaluation_protocols import load_shape, shape_group

__all__ = ["GROUPS", "boxplot_figure", "shape_figure"]

GROUPS = {
    "single": "single-pattern shapes",
    "multi": "Multi_Models shapes",
    "task": "pick-and-place sets",
}


def boxplot_figure(rows, groups, protocols, generators):
    """Box plots of DTW/range per generator, one panel per group and protocol."""
    fig, grid = plot.new_grid(
        len(groups), len(protocols), size=(1.5 + 0.8 * len(generators), 3.8)
    )
    for (group, protocol), ax in zip(
        [(g, p) for g in groups for p in protocols],
        [ax for row in grid for ax in row],
        strict=True,
    ):
        values = {
            gen: [
                r["dtw"]
                for r in rows
                if r["group"] == group
                and r["protocol"] == protocol
                and r["generator"] == gen
            ]
            for gen in generators
        }
        plot.plot_boxplot(
            values,
            ax=ax,
            log=True,
            ylabel="DTW / range",
            title=f"{GROUPS[group]}, {protocol}",
        )
    return fig


def shape_figure(shape: str, example: dict, protocols, generators):
    """The shape's first fold: demonstrations and paths, a panel per protocol.

    The via point is a black diamond, the observed prefix a thick black line;
    a last panel draws the samples (:data:`~._evaluation_protocols.SAMPLES`
    paths drawn from the model, thin red lines) when there are some.
    """
    demos = [_top_view(d) for d in load_shape(shape)]
    k = example["fold"]
    train = [d for i, d in enumerate(demos) if i != k]
    samples = [np.asarray(S)[:, :2] for S in example.get("samples") or []]
    fig, axes = plot.new_figure(len(protocols) + bool(samples), size=(4.5, 4.2))
    for ax, protocol in zip(axes, protocols, strict=False):
        paths, stds = (
            {
                g: np.asarray(example[kind][protocol, g])[:, :2]
                for g in generators
                if (protocol, g) in example[kind]
            }
            for kind in ("paths", "stds")
        )
        plot.plot_comparison(
            train,
            demos[k],
            paths,
            stds=stds,
            ax=ax,
            title=f"{shape}, demo {k} held out, {protocol}",
        )
        _mark_conditions(ax, example.get("conditions", {}).get(protocol, {}))
    if samples:
        ax = axes[-1]
        plot.plot_comparison(train, demos[k], {}, ax=ax)
        for i, S in enumerate(samples):
            ax.plot(
                S[:, 0],
                S[:, 1],
                color=plot.GEN_COLOR,
                lw=0.6,
                alpha=0.7,
                label=f"{len(samples)} samples" if i == 0 else None,
            )
        ax.set_title(f"{shape}, samples from the model (demo {k} held out)")
        ax.legend(loc="best", fontsize="small")
    return fig


def _top_view(demo):
    """A demonstration's position seen from above (x, y): 3-D sets in 2-D panels."""
    return Demonstration.from_arrays(demo.t, position=demo.get("position")[:, :2])


def _mark_conditions(ax, kw: dict) -> None:
    for i, (name, pose) in enumerate((kw.get("frames") or {}).items()):
        ax.plot(
            pose[0], pose[1], "s", mfc="none", color="black", markersize=9,
            label="task frames (ndlfd)" if i == 0 else None,
        )  # fmt: skip
        ax.annotate(name, (pose[0], pose[1]), fontsize="small",
                    xytext=(6, 6), textcoords="offset points")  # fmt: skip
    for i, (_, p) in enumerate(kw.get("via") or []):
        ax.plot(
            p[0], p[1], "D", color="black", markersize=7,
            label="via point" if i == 0 else None,
        )  # fmt: skip
    observed = kw.get("observed")
    if observed is not None:
        obs = np.asarray(observed, dtype=float)
        ax.plot(obs[:, 0], obs[:, 1], color="black", lw=3.0, label="observed")
    if kw.get("via") or kw.get("frames") or observed is not None:
        ax.legend(loc="best", fontsize="small")


def present_groups(shapes) -> list[str]:
    """The groups of :data:`GROUPS` that hold one of the shapes, in order."""
    present = {shape_group(s) for s in shapes}
    return [g for g in GROUPS if g in present]
