"""Task frames: time per call, with and without frames, ProMP conditioning beside.

``synth.pick_place`` turned by up to 60 deg (12 demonstrations of 300
samples, 3-D position, orientation, gripper): the default model fitted on 11,
the 12th held out. Timed (median and largest of 21 calls after a warm-up):

* ``generate(t, dense=True, start=...)``, without and with the held-out
  frames (``frames=``; the frames' step is kept in the model's cache per plan
  and frames, so the first call with new frames is timed apart);
* replanning: ``generate(t, dense=True, observed=prefix)`` with the prefix
  growing from 10 % to 90 % of the samples, without and with frames;
* ProMP (``movement_primitives`` through ``ndlfd.baselines``, fitted on the
  positions) conditioned on the start, the grasp and the goal, what the
  ``frames`` protocol of ``ndlfd evaluate`` gives it.

Run: ``.venv/bin/python benchmarks/bench_frames.py`` (a few seconds).
"""

from __future__ import annotations

import time

import numpy as np

from ndlfd import Demonstration, KeypointHMM, synth
from ndlfd.baselines import make_baseline


def timed(f, repeat=21):
    f()  # warm-up
    out = []
    for _ in range(repeat):
        t0 = time.perf_counter()
        f()
        out.append(time.perf_counter() - t0)
    return 1000 * np.median(out), 1000 * max(out)


def main() -> None:
    demos, _ = synth.pick_place(12, yaw=np.radians(60))
    train, test = demos[1:], demos[0]
    model = KeypointHMM().fit(train)
    t, P = test.t, test.get("position")
    start = {"position": P[0]}
    frames = dict(test.frames)
    rows = []
    plain = timed(lambda: model.generate(t, dense=True, start=start))
    rows.append(("generate, start", *plain))
    fresh = KeypointHMM().fit(train)
    t0 = time.perf_counter()
    fresh.generate(t, dense=True, start=start, frames=frames)
    first = 1000 * (time.perf_counter() - t0)
    rows.append(("generate, start and frames: first call", first, first))
    rows.append(("generate, start and frames: again",
                 *timed(lambda: model.generate(t, dense=True, start=start,
                                               frames=frames))))  # fmt: skip
    cuts = np.linspace(0.1 * t.size, 0.9 * t.size, 21).astype(int)

    def ticks(**kw):
        out = []
        for n in cuts:
            pre = Demonstration(t[:n], test.X[:n], test.columns, test.groups)
            t0 = time.perf_counter()
            model.generate(t, dense=True, observed=pre, **kw)
            out.append(time.perf_counter() - t0)
        return 1000 * np.median(out[1:]), 1000 * max(out[1:])

    ticks()  # the routes and the skeleton, once
    rows.append(("replanning tick (21 prefixes)", *ticks()))
    ticks(frames=frames)
    rows.append(("replanning tick with frames", *ticks(frames=frames)))
    g = round(synth.PICK_PLACE_GRASP * (t.size - 1))
    promp = make_baseline("promp").fit([d.select("position") for d in train])
    pins = [(t[g], P[g]), (t[-1], P[-1])]
    rows.append(("ProMP: start, grasp and goal",
                 *timed(lambda: promp.generate(t, start=P[0], via=pins))))  # fmt: skip
    print("pick_place (turned up to 60 deg), 11 demonstrations of 300 samples")
    print("| call | median ms | largest ms |")
    print("|---|---:|---:|")
    for name, med, top in rows:
        print(f"| {name} | {med:.2f} | {top:.2f} |")


if __name__ == "__main__":
    main()
