"""
A robot's limits: velocity, acceleration and speed
==================================================

A generated path follows the timing it was asked for; a robot has maximum
velocities and accelerations per axis (or joint), and often a largest speed of
its tool (the norm of the position's velocity). :func:`ndlfd.limits.time_scale`
slows a path down where it exceeds them (TOPP-RA, ``pip install
"ndlfd[limits]"``) and keeps it as it is elsewhere; ``generate(limits=...)``
does the same in one call. :func:`ndlfd.limits.path_peaks` measures a path's
peaks as a controller sampling it sees them.
"""

import matplotlib.pyplot as plt
import numpy as np

import ndlfd
from ndlfd.limits import path_peaks, time_scale

# %%
# A path generated too fast
# -------------------------
# A square of demonstrations, generated over 2 s instead of its usual pace.
train, _ = ndlfd.synth.make_dataset("square", n_demos=10, random_state=1)
model = ndlfd.KeypointHMM(groups=("position",), n_time_bins=30).fit(train)
path = model.generate(np.linspace(0.0, 2.0, 200), dense=True)
peaks = path_peaks(path)
print(
    "peak velocity per axis:",
    peaks["velocity"].round(2),
    " peak speed:",
    peaks["speed"][0].round(2),
)

# %%
# Per-axis limits, then a speed limit
# -----------------------------------
axes = {"position": {"velocity": 10.0, "acceleration": 200.0}}
speed = {"position": {"speed": 10.0, "acceleration": 200.0}}
by_axis = time_scale(path, axes)
by_speed = time_scale(path, speed)
for name, p in (("per axis", by_axis), ("speed", by_speed)):
    k = path_peaks(p)
    print(
        f"{name}: {p.duration:.2f} s, peak velocity {k['velocity'].round(2)}, "
        f"speed {k['speed'][0]:.2f}, acceleration {k['acceleration'].round(2)}"
    )

# the same in one call
limited = model.generate(np.linspace(0.0, 2.0, 200), dense=True, limits=speed)
print(f"generate(limits=...): {limited.duration:.2f} s")


# %%
# Speed over time
# ---------------
# A speed limit holds the tool's speed however the motion is oriented; per-axis
# limits let a diagonal move reach sqrt(2) times the axis limit.
def speed_of(p):
    """The norm of the position's velocity at each sample."""
    v = np.gradient(p.get("position"), p.t, axis=0)
    return np.linalg.norm(v, axis=1)


fig, ax = plt.subplots(figsize=(6.5, 3))
ax.plot(path.t, speed_of(path), color="0.6", label="as generated")
ax.plot(by_axis.t, speed_of(by_axis), label="velocity 10 per axis")
ax.plot(by_speed.t, speed_of(by_speed), label="speed 10")
ax.axhline(10.0, color="k", lw=0.8, ls=":")
ax.set_xlabel("time (s)")
ax.set_ylabel("speed")
ax.legend(fontsize=8)
fig.tight_layout()
