"""Task frames around a fixed post: clearance and grasp, leave one out.

The sets of ``tests/frames_obstacle.py`` (a pick-and-place from a fixed home
past a fixed vertical post, to an object moved by up to 10 cm and turned by
up to 30 deg, back past the post to a fixed place; timing +-15 % per piece,
waypoint jitter and noise): one route (every demonstration out on the left
of the post and back on its right) and two routes (some out on the right).
Each demonstration is held out in turn; the others fit

* ndlfd given the held-out start and object frame (what the ``frames``
  protocol of ``ndlfd evaluate`` gives a generator that takes frames), and
  given the first fifth of the held-out motion as a prefix with the frame
  (replanning);
* ProMP (``ndlfd.baselines``, on the positions) given the start, the grasp
  (the held-out position when the hand reaches the object) and the goal as
  via points (what the ``frames`` protocol gives the others);
* the object-frame mean: every training demonstration carried rigidly to the
  held-out object's pose, averaged on one clock (following the object's
  frame everywhere).

Printed per set and generator: the smallest clearance to the post's centre
line over the folds and its median, as a share of the training
demonstrations' smallest; how many folds keep less than 0.8 of it; the
grasp error (closest approach to the held-out object, mm), median and
largest.

Run: ``.venv/bin/python benchmarks/bench_frames_world.py`` (about five
minutes, most of it ProMP's).
"""

from __future__ import annotations

import sys
import warnings
from pathlib import Path

import numpy as np

sys.path.insert(0, str(Path(__file__).resolve().parents[1] / "tests"))

from frames_obstacle import (
    clearance,
    grasp_error,
    object_frame_mean,
    pick_around,
)
from ndlfd import Demonstration, KeypointHMM
from ndlfd.baselines import make_baseline

SETS = {
    "one route, 14 demos": {"n_demos": 14, "n_right": 0},
    "two routes, 14 demos (10 + 4)": {"n_demos": 14, "n_right": 4},
    "two routes, 10 demos (6 + 4)": {"n_demos": 10, "n_right": 4},
    "two routes, 8 demos (5 + 3)": {"n_demos": 8, "n_right": 3},
}
SEEDS = (0, 1, 2)


def fold(demos, grasps, k) -> dict:
    """Every generator's path for held-out demonstration ``k``."""
    test, train = demos[k], demos[:k] + demos[k + 1 :]
    t, P = test.t, test.get("position")
    frames = dict(test.frames)
    model = KeypointHMM().fit(train)
    cut = test.n_samples // 5
    pre = Demonstration(t[:cut], test.X[:cut], test.columns, test.groups)
    g = int(np.argmin(np.abs(t - grasps[k])))
    promp = make_baseline("promp").fit([d.select("position") for d in train])
    with warnings.catch_warnings():
        warnings.simplefilter("ignore")  # a far start or a minor route
        paths = {
            "ndlfd (start, frames)": model.generate(
                t, dense=True, frames=frames, start={"position": P[0]}
            ).get("position"),
            "ndlfd (prefix, frames)": model.generate(
                t, dense=True, frames=frames, observed=pre
            ).get("position"),
        }
    paths["ProMP (start, grasp, goal)"] = np.asarray(
        promp.generate(t, start=P[0], via=[(t[g], P[g]), (t[-1], P[-1])])
    )
    paths["object-frame mean"] = object_frame_mean(train, frames["object"], t)
    smallest = min(clearance(d.get("position")) for d in train)
    obj = frames["object"]
    return {
        name: (clearance(Q) / smallest, 1000 * grasp_error(Q, obj))
        for name, Q in paths.items()
    }


def main() -> None:
    print("| set | generator | clearance / demos' smallest: min, median |"
          " folds < 0.8 | grasp error mm: median, max |")  # fmt: skip
    print("|---|---|---:|---:|---:|")
    for label, kw in SETS.items():
        rows: dict[str, list] = {}
        for seed in SEEDS:
            demos, grasps = pick_around(random_state=seed, **kw)
            for k in range(len(demos)):
                for name, r in fold(demos, grasps, k).items():
                    rows.setdefault(name, []).append(r)
        for name, r in rows.items():
            a = np.array(r)
            print(
                f"| {label} | {name} | {a[:, 0].min():.2f}, {np.median(a[:, 0]):.2f}"
                f" | {int((a[:, 0] < 0.8).sum())}/{len(a)}"
                f" | {np.median(a[:, 1]):.1f}, {a[:, 1].max():.1f} |"
            )


if __name__ == "__main__":
    main()
