"""Pick-and-place with a moved (and turned) object: ndlfd against ProMP-via.

``synth.pick_place`` (12 demonstrations; the object and the place moved by up
to 0.1 m, and with ``--yaw`` turned by up to that many degrees), each held
out in turn, the others fitted. Given the held-out start, goal and the hand's
position at its grasp (the object's position) as a via point at the true
grasp time:

* ``ndlfd s+g``: ndlfd given the start and goal only;
* ``ndlfd via``: ndlfd given the start, the goal and the via point;
* ``ndlfd frames``: ndlfd given the start and the held-out demonstration's
  task frames (the object's and the place's poses; no time, no goal);
* ``promp via``: ProMP (movement_primitives) conditioned on the start, the via
  point and the goal (a via point at the last time stamp), position only.

Prints the median over the folds of DTW (``dtw_distance(normalize=True)``)
over the demonstrations' range, on the position, and the grasp error (the
path's distance to the object at the grasp time).

Run: ``.venv/bin/python benchmarks/probe_task_frames.py [--yaw 60]``
"""

from __future__ import annotations

import argparse

import numpy as np

from ndlfd import KeypointHMM, synth
from ndlfd.baselines import make_baseline
from ndlfd.metrics import dtw_distance


def main(argv=None) -> None:
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("--yaw", type=float, default=0.0, help="degrees")
    ap.add_argument("--demos", type=int, default=12)
    args = ap.parse_args(argv)
    demos, frames = synth.pick_place(args.demos, yaw=np.deg2rad(args.yaw))
    P_all = np.vstack([d.get("position") for d in demos])
    scale = float(np.linalg.norm(np.ptp(P_all, axis=0)))
    rows = {"ndlfd s+g": [], "ndlfd via": [], "ndlfd frames": [], "promp via": []}
    demos = [d.with_frames(f) for d, f in zip(demos, frames, strict=True)]
    grasp = {k: [] for k in rows}
    for k, test in enumerate(demos):
        train = [d for i, d in enumerate(demos) if i != k]
        t = test.t
        g = int(np.rint(synth.PICK_PLACE_GRASP * (t.size - 1)))
        P = test.get("position")
        obj = frames[k]["object"][:3]
        model = KeypointHMM().fit(train)
        start, goal = {"position": P[0]}, {"position": P[-1]}
        via = [(t[g], {"position": obj})]
        paths = {
            "ndlfd s+g": model.generate(t, dense=True, start=start, goal=goal),
            "ndlfd via": model.generate(t, dense=True, start=start, goal=goal, via=via),
            "ndlfd frames": model.generate(
                t, dense=True, start=start, frames=dict(test.frames)
            ),
        }
        paths = {name: p.get("position") for name, p in paths.items()}
        promp = make_baseline("promp").fit([d.select("position") for d in train])
        pins = [(t[g], obj), (t[-1], P[-1])]
        paths["promp via"] = promp.generate(t, start=P[0], via=pins)
        for name, Q in paths.items():
            rows[name].append(dtw_distance(Q, P, normalize=True) / scale)
            grasp[name].append(float(np.linalg.norm(Q[g] - obj)))
    print(f"pick_place, {args.demos} demonstrations, shift 0.1 m, yaw {args.yaw:g} deg")
    print("| generator | DTW/range (median) | grasp error m (median) |")
    print("|---|---:|---:|")
    for name in rows:
        print(
            f"| {name} | {np.median(rows[name]):.4f} | {np.median(grasp[name]):.4f} |"
        )
    for name in ("ndlfd via", "ndlfd frames"):
        ratio = np.median(rows[name]) / np.median(rows["promp via"])
        print(f"{name} / promp via: {ratio:.2f}")


if __name__ == "__main__":
    main()
