"""A grasp is held (issue 39): drift during the hold and dip below the via point.

The grasp sets of ``tests/learner/test_learner_rests.py`` (the hand comes
down onto an object, holds 0.6 s while the gripper closes, lifts and carries
it away; 8 demonstrations, objects within 5 cm), fitted on many seeds of its
generator, in Cartesian space (``position``) and in a planar arm's joint
space (``joints``, the hand by forward kinematics). Each model generates for
new executions' timings (the test's ``_plans``, drawn per seed) with a via
point at an object (up to 6 cm outside the demonstrations' places, the
test's ``OBJECTS``) at the first time stamp of the hold, with and without a
start off home. Drift: the hand's largest distance from the object over the
next 0.5 s (the demonstrations hold 0.51 to 0.69 s); dip: how far the hand
goes below the object at any time.

Run: ``.venv/bin/python benchmarks/probe_rests.py [n_seeds]`` (default 40).

Measured, 40 seeds (1,920 paths per space), drift median / largest (mm),
largest dip (mm):

* before (a joint via point off the blend's clock; a hold out of the
  clock's reach; the templates' holds smeared in the blend): joints 1.26 /
  41.0 (p95 13.7), dip 41.0; Cartesian 0.78 / 26.3 (p95 2.74), dip 26.2.
* after (a joint via point warps the clock and conditions the blend, a hold
  near the via time read at its start on a clock that may bend 3 times
  more, the templates' holds aligned in the conditioned blend and its shift
  averaged over the time spent moving): joints 0.56 / 2.10 (p95 1.23), dip
  1.64; Cartesian 0.62 / 1.64 (p95 0.93), dip 1.15.
"""

from __future__ import annotations

import sys
import time
import warnings
from pathlib import Path

import numpy as np

sys.path.insert(0, str(Path(__file__).resolve().parent.parent / "tests" / "learner"))
import test_learner_rests as grasp


def _cases(space: str, seed: int):
    """Per path: (seed, object, plan, start) and the drift and dip (m)."""
    fit = grasp.joint_set if space == "joints" else grasp.cartesian_set
    _, model = fit(seed=seed)
    out = []
    home = grasp.HOME
    for i, obj in enumerate(map(np.array, grasp.OBJECTS)):
        for k, (t, tv, hold) in enumerate(grasp._plans(seed=1000 + seed)):
            for s in (0, 1):
                if space == "joints":
                    o = obj[[0, 2]]
                    start = {"joints": grasp.ik(home[None, [0, 2]])[0] + 0.05}
                    via = {"joints": grasp.ik(o[None])[0]}
                else:
                    o = obj
                    start = {"position": home + [0.03, -0.04, 0.0]}
                    via = {"position": obj}
                path = model.generate(
                    t, dense=True, start=start if s else None, via=[(tv, via)]
                )
                H = grasp.fk(path.get("joints")) if space == "joints" else None
                H = path.get("position") if H is None else H
                drift = float(np.linalg.norm(H[hold] - o, axis=1).max())
                dip = float(o[-1] - H[:, -1].min())
                out.append(((seed, i, k, s), drift, dip))
    return out


def run(n_seeds: int = 40) -> dict:
    """Median and largest drift, largest dip (mm) per space, the worst cases."""
    warnings.simplefilter("ignore")  # jittery stamps, objects off the range
    report = {}
    for space in ("joints", "position"):
        rows = [r for s in range(n_seeds) for r in _cases(space, s)]
        drift = np.array([d for _, d, _ in rows]) * 1e3
        dip = np.array([d for _, _, d in rows]) * 1e3
        worst = [(rows[j][0], round(float(drift[j]), 2))
                 for j in np.argsort(drift)[::-1][:5]]  # fmt: skip
        report[space] = dict(
            median=float(np.median(drift)),
            p95=float(np.quantile(drift, 0.95)),
            max=float(drift.max()),
            dip=float(dip.max()),
            n=drift.size,
            worst=worst,
        )
    return report


def main(argv) -> None:
    n = int(argv[0]) if argv else 40
    t0 = time.perf_counter()
    for space, r in run(n).items():
        print(
            f"{space:8s} n={r['n']}: drift median {r['median']:.2f} mm,"
            f" p95 {r['p95']:.2f}, max {r['max']:.2f}; largest dip {r['dip']:.2f} mm"
        )
        print("   worst (seed, object, plan, start):", r["worst"])
    print(f"{time.perf_counter() - t0:.0f} s")


if __name__ == "__main__":
    main(sys.argv[1:])
