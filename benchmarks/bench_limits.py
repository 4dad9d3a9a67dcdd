"""What time-scaling a path to a robot's limits costs (ndlfd.limits).

For generated paths of 250, 1,000 and 4,000 samples (SO-101-like joints in
degrees, six columns; the obstacle set's 2-D position), the time of
:func:`ndlfd.limits.time_scale` under velocity and acceleration limits of 60 %
of the path's own peaks, against one bare TOPP-RA call on the same path and
limits (spline, constraints, parameterization and sampling, no checks) in
the same run: the ratio is what ndlfd adds (the checks, the measured peaks,
carrying the other groups along, a retry when the samples overshoot).
Best of 5.

Run: ``.venv/bin/python benchmarks/bench_limits.py``
"""

from __future__ import annotations

import sys
import time
from pathlib import Path

import numpy as np
import toppra
import toppra.algorithm
import toppra.constraint

from ndlfd import KeypointHMM, synth
from ndlfd.limits import path_peaks, time_scale

sys.path.insert(0, str(Path(__file__).resolve().parents[1] / "tests" / "learner"))


def bare_toppra(path, cols, v, a):
    t = path.t - path.t[0]
    spl = toppra.SplineInterpolator(t, path.X[:, cols])
    con = toppra.constraint
    algo = toppra.algorithm.TOPPRA(
        [
            con.JointVelocityConstraint(np.column_stack([-v, v])),
            con.JointAccelerationConstraint(np.column_stack([-a, a])),
        ],
        spl,
        gridpoints=np.linspace(0.0, t[-1], min(20_000, 3 * path.n_samples)),
        parametrizer="ParametrizeConstAccel",
    )
    traj = algo.compute_trajectory(0.0, 0.0)
    return traj(np.arange(0.0, traj.duration, np.median(np.diff(path.t))))


def best(f, repeat=5):
    out = []
    for _ in range(repeat):
        t0 = time.perf_counter()
        f()
        out.append(time.perf_counter() - t0)
    return min(out)


def main() -> None:
    from test_learner_replan import _resting

    _, joints = _resting()
    obstacle = KeypointHMM().fit(synth.obstacle(7, 5))
    print("| path | samples | time_scale ms | bare TOPP-RA ms | ratio | duration |")
    print("|---|---:|---:|---:|---:|---|")
    sets = (
        ("SO-101-like joints", joints, "joints", 15.0),
        ("obstacle position", obstacle, "position", 5.0),
    )
    for name, model, group, T in sets:
        for n in (250, 1000, 4000):
            path = model.generate(np.linspace(0.0, T, n), dense=True)
            cols = path.columns_of(group)
            peaks = path_peaks(path)
            v, a = 0.6 * peaks["velocity"][cols], 0.6 * peaks["acceleration"][cols]
            lim = {"velocity": {group: v}, "acceleration": {group: a}}
            ours = best(lambda path=path, lim=lim: time_scale(path, lim))
            bare = best(
                lambda path=path, cols=cols, v=v, a=a: bare_toppra(path, cols, v, a)
            )
            out = time_scale(path, lim)
            print(f"| {name} | {n} | {ours * 1e3:.1f} | {bare * 1e3:.1f} |"
                  f" {ours / bare:.2f} | {path.duration:.1f} s ->"
                  f" {out.duration:.1f} s |")  # fmt: skip


if __name__ == "__main__":
    main()
