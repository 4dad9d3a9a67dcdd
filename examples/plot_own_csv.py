"""
Your own recordings: CSV files from a lab
=========================================

Recordings rarely follow a naming convention and often have no time column:
here six reaches logged at 20 Hz by a lab's export, one semicolon-separated
file each, with columns ``pos_x;pos_y;pos_z;gripper`` and no time.
:func:`ndlfd.io.read_demos` reads a folder of them with ``rate=20`` (row ``k``
at ``k / 20`` s) and says how it mapped the columns to groups; the model
learns every group it finds, generates a path for a new duration with its
band, and ``ndlfd.io.write_csv`` writes the path back under the recordings'
own names.
"""

import tempfile
from pathlib import Path

import matplotlib.pyplot as plt
import numpy as np

import ndlfd
from ndlfd.plot import plot_demos

# %%
# Six lab recordings
# ------------------
folder = Path(tempfile.mkdtemp()) / "reaches"
folder.mkdir()
rng = np.random.default_rng(3)
for i in range(6):
    n = rng.integers(70, 90)  # 3.5-4.5 s at 20 Hz
    s = np.linspace(0.0, 1.0, n)
    ramp = 10 * s**3 - 15 * s**4 + 6 * s**5  # minimum jerk
    x = 0.3 + 0.25 * ramp + rng.normal(0, 0.002, n)
    y = -0.1 + 0.2 * ramp + 0.06 * np.sin(np.pi * ramp) + rng.normal(0, 0.002, n)
    z = 0.25 - 0.2 * ramp + rng.normal(0, 0.002, n)
    gripper = np.where(s < 0.85, 1.0, 0.0)
    table = np.column_stack([x, y, z, gripper])
    np.savetxt(
        folder / f"reach_{i}.csv",
        table,
        delimiter=";",
        fmt="%.5f",
        header="pos_x;pos_y;pos_z;gripper",
        comments="",
    )
print((folder / "reach_0.csv").read_text().splitlines()[:3])

# %%
# Read at 20 Hz, fit
# ------------------
demos, mappings = ndlfd.io.read_demos(folder, rate=20, return_mappings=True)
print(demos[0])
print(mappings[0])
model = ndlfd.KeypointHMM().fit(demos)

# %%
# Generate a 5 s path with its band, write it back
# ------------------------------------------------
t = np.arange(0.0, 5.0, 0.05)
path, std = model.generate(t, dense=True, return_std=True)
out = ndlfd.io.write_csv(
    path, folder.parent / "reach_generated.csv", mapping=mappings[0]
)
print(out.read_text().splitlines()[0])

# %%
# The recordings, the path and its band
# -------------------------------------
# In space, and the height over time with the band of ±1 standard deviation.
fig = plt.figure(figsize=(9, 4))
space = fig.add_subplot(1, 2, 1, projection="3d")
side = fig.add_subplot(1, 2, 2)
plot_demos(demos, ax=space, title="the reaches")
position = path.get("position")
space.plot(*position.T, color="tab:red", lw=2, label="generated")
space.legend(fontsize=8)
z = list(path.columns).index("pos_z")
for d in demos:
    side.plot(d.t, d.get("position")[:, 2], color="0.7", lw=0.8)
side.plot(path.t, position[:, 2], color="tab:red", lw=2)
side.fill_between(
    path.t,
    position[:, 2] - std[:, z],
    position[:, 2] + std[:, z],
    color="tab:red",
    alpha=0.2,
    label="±1 std",
)
side.set_xlabel("time (s)")
side.set_ylabel("z (m)")
side.legend(fontsize=8)
fig.tight_layout()
