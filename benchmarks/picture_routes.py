"""The README's "Several routes" picture: two routes around an obstacle.

Twelve demonstrations from the left to the origin, 7 over the obstacle and 5
under it, each route starting 1 apart. Drawn: the demonstrations, the time-
aligned mean (what averaging gives: through the obstacle), ndlfd's path from
the timing alone (the route most demonstrations take) and from a start on the
other route.

    python benchmarks/picture_routes.py docs/images/routes.png
"""

import sys

import numpy as np

import ndlfd
from ndlfd.metrics import mean_demo_baseline
from ndlfd.synth import obstacle


def main(out):
    import matplotlib

    matplotlib.use("Agg")
    import matplotlib.pyplot as plt

    demos = obstacle(7, 5, lift=1.0)
    model = ndlfd.KeypointHMM().fit(demos)
    t = np.linspace(0.0, 5.0, 200)
    free = model.generate(t, dense=True).get("position")
    low = model.generate(t, dense=True, start={"position": [-10.0, -1.0]})
    low = low.get("position")
    mean = mean_demo_baseline(demos, t)
    fig, ax = plt.subplots(figsize=(7, 4.2))
    ax.add_patch(plt.Circle((-5.0, 0.0), 2.5, color="0.85", zorder=0))
    ax.text(-5.0, 0.0, "obstacle", ha="center", va="center", color="0.4")
    for i, d in enumerate(demos):
        P = d.get("position")
        label = "demonstrations (7 over, 5 under)" if i == 0 else None
        ax.plot(P[:, 0], P[:, 1], color="0.6", lw=0.8, label=label)
    ax.plot(mean[:, 0], mean[:, 1], "k--", lw=1.5, label="time-aligned mean")
    ax.plot(free[:, 0], free[:, 1], color="tab:red", lw=2.2,
            label="ndlfd, timing only: the major route")  # fmt: skip
    ax.plot(low[:, 0], low[:, 1], color="tab:blue", lw=2.2,
            label="ndlfd, start (-10, -1): the route from there")  # fmt: skip
    ax.set_aspect("equal")
    ax.set_xlabel("x")
    ax.set_ylabel("y")
    ax.legend(loc="upper left", fontsize=8, bbox_to_anchor=(1.01, 1.0))
    fig.tight_layout()
    fig.savefig(out, dpi=110)
    print(f"mid-course y: timing only {free[np.argmin(np.abs(free[:, 0] + 5)), 1]:.2f},"
          f" from the low start {low[np.argmin(np.abs(low[:, 0] + 5)), 1]:.2f},"
          f" mean {mean[np.argmin(np.abs(mean[:, 0] + 5)), 1]:.2f}")  # fmt: skip


if __name__ == "__main__":
    main(sys.argv[1] if len(sys.argv) > 1 else "routes.png")
