"""
The paper's procedure, on its square
====================================

ndlfd reproduces the method of the paper it follows: demonstrations are
reduced to key points by an n-dimensional Douglas-Peucker algorithm over
group-normalized channels, the key points are encoded as codebook states, a
supervised discrete HMM learns them, and Viterbi decodes a path for a new
timing. ``KeypointHMM(generation="paper")`` generates as the paper does (the
decoded states' codebook values, joined); the default ``"blend"`` generation
follows the demonstrations themselves between the decoded key points. Here
both on a small version of the paper's square data set (``ndlfd reproduce``
runs the paper's figures whole, in a few seconds).
"""

import matplotlib.pyplot as plt

import ndlfd
from ndlfd.plot import plot_demos

# %%
# The square, as the paper's Fig. 5
# ----------------------------------
train, test = ndlfd.synth.make_dataset("square", n_demos=20, random_state=1)
settings = dict(
    groups=("position", "velocity"),
    levels={"position": 20, "velocity": 10},
    epsilon=0.05,
    n_time_bins=40,
)
paper = ndlfd.KeypointHMM(generation="paper", **settings).fit(train)
blend = ndlfd.KeypointHMM(**settings).fit(train)

# %%
# Key points of the demonstrations
# --------------------------------
# As the model finds them, on the group-normalized channels (five of the
# demonstrations are drawn, with their key points as dots).
scaler = ndlfd.GroupScaler(mode="group").fit(train)
keys = [ndlfd.simplify(scaler.transform(d), 0.05) for d in train]
print("key points per demonstration:", [len(k) for k in keys])

# %%
# Generated for the test's timing
# -------------------------------
fig, axes = plt.subplots(1, 2, figsize=(9, 4.2))
for ax, model, name in ((axes[0], paper, '"paper"'), (axes[1], blend, '"blend"')):
    path = model.generate(test, dense=True)
    error = ndlfd.metrics.dtw_distance(path.get("position"), test.get("position"))
    plot_demos(
        train[:5],
        keypoints=keys[:5],
        generated=path,
        test=test,
        ax=ax,
        title=f"generation={name}: DTW {error:.3g}",
    )
    ax.set_aspect("equal")
fig.tight_layout()
