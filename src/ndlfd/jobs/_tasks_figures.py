"""The task evaluation's figures (:mod:`ndlfd.jobs._tasks`): matplotlib, no display."""

from __future__ import annotations

import numpy as np

__all__ = ["METHOD_STYLES", "failures_top_view", "success_curve"]

#: Each method's line in the success curve: end-effector methods solid, their
#: joint-space counterparts dashed in the same colour (ndlfd-joint with
#: ndlfd-ee, promp-joint with promp, nearest-joint with nearest).
METHOD_STYLES = {
    "ndlfd-ee": {"color": "C0", "ls": "-", "marker": "o"},
    "ndlfd-joint": {"color": "C0", "ls": "--", "marker": "s"},
    "object-mean": {"color": "C2", "ls": "-", "marker": "o"},
    "promp": {"color": "C3", "ls": "-", "marker": "o"},
    "nearest": {"color": "C4", "ls": "-", "marker": "o"},
    "promp-joint": {"color": "C3", "ls": "--", "marker": "s"},
    "nearest-joint": {"color": "C4", "ls": "--", "marker": "s"},
}


def success_curve(result, path) -> None:
    """Success rate against the number of demonstrations, one panel per task.

    Parameters
    ----------
    result : TaskResult
    path : path-like
        The PNG written.
    """
    import matplotlib

    matplotlib.use("Agg")
    import matplotlib.pyplot as plt

    table = result.summary()
    tasks = list(dict.fromkeys(s["task"] for s in table))
    fig, axes = plt.subplots(
        1, len(tasks), figsize=(5 * len(tasks), 3.8), squeeze=False
    )
    for ax, task in zip(axes[0], tasks, strict=True):
        rows = [s for s in table if s["task"] == task]
        for method in dict.fromkeys(s["method"] for s in rows):
            pts = sorted(
                (s["n_demos"], s["success"]) for s in rows if s["method"] == method
            )
            if method == "expert":
                ax.axhline(pts[0][1], color="k", ls=":", label="expert (closed loop)")
                continue
            style = METHOD_STYLES.get(method, {"marker": "o"})
            ax.plot(*zip(*pts, strict=True), label=method, **style)
        ax.set_xscale("log")
        ax.minorticks_off()
        ns = sorted({s["n_demos"] for s in rows if s["n_demos"]})
        ax.set_xticks(ns, [str(n) for n in ns])
        ax.set_ylim(-0.02, 1.02)
        ax.set_xlabel("demonstrations N")
        ax.set_ylabel("success (held-out object poses)")
        ax.set_title(task)
        ax.grid(alpha=0.3)
    axes[0][-1].legend(fontsize=7, loc="best")
    fig.tight_layout()
    fig.savefig(path, dpi=110)
    plt.close(fig)


def failures_top_view(result, task: str, path, *, per_method: int = 12) -> None:
    """Top view (x, y) of failed episodes at the largest N: hands and objects.

    One panel per method: each failed episode's right-hand (solid) and
    left-hand (dashed) tool points as the joints commanded put them, and the
    objects where they were placed (squares); at most ``per_method``
    episodes each.
    """
    import matplotlib

    matplotlib.use("Agg")
    import matplotlib.pyplot as plt

    rows = [r for r in result.rows if r.task == task and r.method != "expert"]
    if not rows:
        return
    n = max(r.n_demos for r in rows)
    methods = list(dict.fromkeys(r.method for r in rows))
    cols = min(len(methods), 4)
    grid = (-(-len(methods) // cols), cols)
    fig, axes = plt.subplots(*grid, figsize=(3.6 * cols, 2.8 * grid[0] + 0.6),
                             squeeze=False, sharey=True)  # fmt: skip
    for ax in axes.flat[len(methods) :]:
        ax.set_visible(False)
    for ax, method in zip(axes.flat, methods, strict=False):
        failed = [
            r for r in rows if r.method == method and r.n_demos == n and not r.success
        ]
        total = sum(1 for r in rows if r.method == method and r.n_demos == n)
        for k, r in enumerate(failed[:per_method]):
            c = plt.cm.tab10(k % 10)
            if r.hands is not None:
                ax.plot(r.hands[:, 1, 0], r.hands[:, 1, 1], color=c, lw=0.9)
                ax.plot(r.hands[:, 0, 0], r.hands[:, 0, 1], color=c, lw=0.9, ls="--")
            obj = np.asarray(r.objects).reshape(-1, 3)
            ax.scatter(obj[:, 0], obj[:, 1], marker="s", color=c, s=20)
        ax.set_title(f"{method}, N={n}: {len(failed)}/{total} failed", fontsize=9)
        ax.set_xlabel("x (m)")
        ax.set_xlim(-0.35, 0.35)
        ax.set_ylim(0.3, 0.7)
        ax.set_aspect("equal")
        ax.grid(alpha=0.3)
    for row in axes:
        row[0].set_ylabel("y (m)")
    fig.suptitle(f"{task}: failed episodes from above (right hand solid, left dashed)",
                 fontsize=10)  # fmt: skip
    fig.tight_layout()
    fig.savefig(path, dpi=110)
    plt.close(fig)
