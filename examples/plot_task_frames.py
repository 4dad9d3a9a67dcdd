"""
Task frames: the object moved
=============================

When the object is somewhere new, what a user knows is where it is, not when
the robot should reach it. Demonstrations can carry *task frames*: poses
constant over a demonstration (a position, then a unit quaternion w, x, y, z).
:func:`ndlfd.synth.pick_place` makes a pick-and-place whose object and place
move and turn between demonstrations; ``generate(frames=...)`` takes their new
poses. Each part of the motion follows the frame in which the demonstrations
agree most: the approach and grasp the object's, the put-down the place's.
"""

import matplotlib.pyplot as plt
import numpy as np

import ndlfd
from ndlfd.plot import plot_demos, plot_frames

# %%
# Demonstrations with frames
# --------------------------
demos, frames = ndlfd.synth.pick_place(12, n_samples=200, yaw=np.radians(60))
print("object pose of the first demonstration:", demos[0].frames["object"].round(3))
model = ndlfd.KeypointHMM().fit(demos)

# %%
# A new object pose, turned by 45 degrees
# ---------------------------------------
# A pose is ``x, y, z, qw, qx, qy, qz``; the place stays where the first
# demonstration had it.
c, s = np.cos(np.radians(45) / 2), np.sin(np.radians(45) / 2)
turned = np.array([0.55, -0.05, 0.02, 0.0, c, s, 0.0])
new = {"object": turned, "place": demos[0].frames["place"]}
path = model.generate(
    demos[0].t, dense=True, frames=new, start={"position": [0.3, 0.0, 0.3]}
)
grasp = round(ndlfd.synth.PICK_PLACE_GRASP * (path.n_samples - 1))
miss = np.linalg.norm(path.get("position")[grasp] - turned[:3])
print(f"grasp {1000 * miss:.1f} mm from the new object")

# %%
# In space
# --------
# The demonstrations with their frames (grey), the new frames (red) and the
# generated path.
fig = plt.figure(figsize=(6, 5))
ax = fig.add_subplot(projection="3d")
plot_demos(demos, ax=ax, title="Pick and place, object moved and turned")
plot_frames(ax, frames, colors="0.5", names=["object", "place"])
plot_frames(ax, [new], colors="tab:red", names=["object", "place"], label="new {name}")
ax.plot(*path.get("position").T, color="tab:red", lw=2, label="generated")
ax.view_init(elev=55, azim=-120)
ax.legend(fontsize=7, loc="lower left")
fig.tight_layout()

# %%
# The gripper over time
# ---------------------
# Closed (0) between the grasp and the release, as demonstrated.
fig, ax = plt.subplots(figsize=(6, 2.2))
for d in demos:
    ax.plot(d.t, d.get("gripper"), color="0.7", lw=0.8)
ax.plot(path.t, path.get("gripper"), color="tab:red", lw=2)
ax.set_xlabel("time (s)")
ax.set_ylabel("gripper")
fig.tight_layout()
