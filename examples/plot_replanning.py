"""
Replanning from an observed prefix at 10 Hz
===========================================

During an execution, ``model.generate(t, observed=prefix)`` takes the samples
executed so far (at the first time stamps of ``t``) and returns them followed
by the rest of the path, continued from the last one without a jump. Here a
robot executes a demonstration of the lower route around an obstacle that the
model never saw, and replans every 0.1 s. While the prefix is ambiguous the
plan follows the route most demonstrations take (the upper one); once the
prefix has left that route's demonstrations by more than they stray from each
other, the plan commits to the lower route, once, and never goes back.
"""

import matplotlib.pyplot as plt
import numpy as np

import ndlfd

# %%
# Fit without the episode to execute
# ----------------------------------
demos = ndlfd.synth.obstacle(7, 5, n_samples=150)
episode = demos.pop(-1)  # a lower-route demonstration, held out
model = ndlfd.KeypointHMM().fit(demos)

# %%
# Replan at 10 Hz
# ---------------
# The prefix is the episode up to now; every plan is on the episode's clock.
step = np.median(np.diff(episode.t))
every = max(1, round(0.1 / step))  # samples between two replans
plans = []
for m in range(every, episode.n_samples - every, every):
    prefix = ndlfd.Demonstration(
        episode.t[:m], episode.X[:m], episode.columns, episode.groups
    )
    path = model.generate(episode.t, dense=True, observed=prefix)
    plans.append((episode.t[m - 1], path.get("position")))
side = np.array([np.sign(P[np.argmin(np.abs(P[:, 0] + 5.0)), 1]) for _, P in plans])
commit = int(np.flatnonzero(side < 0)[0])
print(
    f"{len(plans)} plans; the plan takes the lower route from t = "
    f"{plans[commit][0]:.1f} s on; route changes: {np.count_nonzero(np.diff(side))}"
)

# %%
# Every fifth plan, coloured by when it was made
# ----------------------------------------------
fig, ax = plt.subplots(figsize=(7, 4))
ax.add_patch(plt.Circle((-5.0, 0.0), 2.5, color="0.85", zorder=0))
for d in demos:
    ax.plot(*d.get("position").T, color="0.75", lw=0.7)
colors = plt.cm.viridis(np.linspace(0, 1, len(plans)))
for i in range(0, len(plans), 5):
    ax.plot(*plans[i][1].T, color=colors[i], lw=1.2)
ax.plot(*episode.get("position").T, "k--", lw=1.2, label="executed episode")
sm = plt.cm.ScalarMappable(
    cmap="viridis", norm=plt.Normalize(plans[0][0], plans[-1][0])
)
fig.colorbar(sm, ax=ax, label="plan made at (s)")
ax.set_aspect("equal")
ax.legend(loc="lower left", fontsize=8)
fig.tight_layout()
