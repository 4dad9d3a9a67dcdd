"""
Two routes around an obstacle
=============================

Demonstrations of one skill often take different routes: here 7 go over an
obstacle and 5 under it. A mean of them runs through the obstacle, which no
demonstration did. :class:`~ndlfd.learner.KeypointHMM` finds the routes when it
fits (``model.routes_``) and follows one: from the timing alone the route most
demonstrations take, from a start the route that starts there. Samples
(:meth:`~ndlfd.learner.KeypointHMM.sample`) stay on the route they are given.
"""

import matplotlib.pyplot as plt
import numpy as np

import ndlfd
from ndlfd.metrics import mean_demo_baseline
from ndlfd.plot import plot_demos, plot_samples

# %%
# Demonstrations and a model
# --------------------------
# :func:`ndlfd.synth.obstacle` draws the two routes, each starting 1 apart.
demos = ndlfd.synth.obstacle(7, 5, n_samples=120, lift=1.0)
model = ndlfd.KeypointHMM().fit(demos)
print("route of each demonstration:", model.routes_)

# %%
# Generate from the timing alone, from a start, and sample
# --------------------------------------------------------
t = np.linspace(0.0, 5.0, 150)
free = model.generate(t, dense=True)
low = model.generate(t, dense=True, start={"position": [-10.0, -1.0]})
samples = model.sample(t, 5, start={"position": [-10.0, -1.0]}, random_state=0)
mean = mean_demo_baseline(demos, t)


def mid_y(P):
    """The path's height where it passes the obstacle (x = -5)."""
    return P[np.argmin(np.abs(P[:, 0] + 5.0)), 1]


print(
    f"mid-course y: timing only {mid_y(free.get('position')):.2f}, "
    f"from the low start {mid_y(low.get('position')):.2f}, "
    f"mean {mid_y(mean):.2f}"
)

# %%
# The picture
# -----------
# The demonstrations coloured by route, the mean (dashed) through the
# obstacle, ndlfd's two paths and five samples from the low start.
fig, ax = plt.subplots(figsize=(7, 4.2))
ax.add_patch(plt.Circle((-5.0, 0.0), 2.5, color="0.85", zorder=0))
plot_demos(demos, routes=model.routes_, ax=ax, title="Two routes")
ax.plot(mean[:, 0], mean[:, 1], "k--", lw=1.5, label="time-aligned mean")
plot_samples(ax, [s.get("position") for s in samples], label="samples, low start")
ax.plot(*free.get("position").T, color="tab:red", lw=2.2, label="timing only")
ax.plot(*low.get("position").T, color="tab:blue", lw=2.2, label="start (-10, -1)")
ax.set_aspect("equal")
ax.legend(loc="upper left", fontsize=7, bbox_to_anchor=(1.01, 1.0))
fig.tight_layout()
