"""The README's "Task frames" picture: a pick-and-place whose object moved and turned.

``synth.pick_place`` turned by up to 60 deg (12 demonstrations; the hand comes
down from behind the object, along the object's own x axis, and puts it down
from behind the place): the demonstration whose object is turned most is held
out and the rest fitted. Drawn from above (x, y): the demonstrations, the
held-out one (dashed), ndlfd given its start and the object's and the place's
new poses (``frames=``, no time), and ProMP given its start, the grasp
position at the true grasp time and the goal. Each frame's x axis is an arrow.

    python benchmarks/picture_task_frames.py docs/images/task-frames.png
"""

import sys

import numpy as np

from ndlfd import KeypointHMM, synth
from ndlfd.baselines import make_baseline
from ndlfd.metrics import dtw_distance


def _yaw(pose) -> float:
    w, z = pose[3], pose[6]
    return 2.0 * np.arctan2(z, w)


def main(out):
    import matplotlib

    matplotlib.use("Agg")
    import matplotlib.pyplot as plt

    demos, frames = synth.pick_place(12, yaw=np.deg2rad(60))
    k = int(np.argmax([abs(_yaw(f["object"])) for f in frames]))
    test, train = demos[k], [d for i, d in enumerate(demos) if i != k]
    t, P = test.t, test.get("position")
    g = int(np.rint(synth.PICK_PLACE_GRASP * (t.size - 1)))
    model = KeypointHMM().fit(train)
    ours = model.generate(t, dense=True, start={"position": P[0]},
                          frames=dict(test.frames)).get("position")  # fmt: skip
    promp = make_baseline("promp").fit([d.select("position") for d in train])
    theirs = promp.generate(t, start=P[0], via=[(t[g], P[g]), (t[-1], P[-1])])
    scale = float(
        np.linalg.norm(np.ptp(np.vstack([d.get("position") for d in demos]), 0))
    )
    fig, ax = plt.subplots(figsize=(6.4, 5.6))
    for i, d in enumerate(train):
        Q = d.get("position")
        ax.plot(Q[:, 0], Q[:, 1], color="0.75", lw=0.8,
                label="demonstrations" if i == 0 else None)  # fmt: skip
    ax.plot(P[:, 0], P[:, 1], "k--", lw=1.4, label="held out (truth)")
    for name, Q, color in (("ndlfd, frames", ours, "tab:red"),
                           ("ProMP, grasp and goal", theirs, "tab:blue")):  # fmt: skip
        d = dtw_distance(Q, P, normalize=True) / scale
        ax.plot(Q[:, 0], Q[:, 1], color=color, lw=1.8, label=f"{name} (DTW {d:.4f})")
    for name, pose in test.frames.items():
        a = _yaw(pose)
        ax.annotate("", xy=(pose[0] + 0.06 * np.cos(a), pose[1] + 0.06 * np.sin(a)),
                    xytext=(pose[0], pose[1]),
                    arrowprops={"arrowstyle": "->", "lw": 2})  # fmt: skip
        ax.text(pose[0] + 0.01, pose[1] - 0.03, f"{name} ({np.degrees(a):+.0f} deg)")
    ax.set_aspect("equal")
    ax.set_xlabel("x (m)")
    ax.set_ylabel("y (m)")
    ax.set_title("pick and place, seen from above: object and place moved and turned")
    ax.legend(loc="upper left", fontsize="small")
    fig.tight_layout()
    fig.savefig(out, dpi=110)
    print(f"wrote {out}; held out demonstration {k}")


if __name__ == "__main__":
    main(sys.argv[1] if len(sys.argv) > 1 else "task-frames.png")
