"""Sampling: time of KeypointHMM.sample per drawn path, and the routes drawn.

1. **Two routes.** 12 demonstrations around an obstacle (9 above, 3 below,
   200 samples each, as ``tests/learner/test_learner_routes.py``'s
   ``obstacle``), the default model. After the fit (and one warm-up draw):
   the time per drawn path of 400 time stamps (``sample(t, 20)``, best of 7,
   divided by 20), the time of the skeletons alone
   (:func:`ndlfd.hmm.sample_paths`, 400 of them), and the share of 200 draws
   on the major route. Target (issue 17): <= 5 ms per 400-sample draw,
   75 % +- 10 % on the major route.
2. **Scale.** The 100 3-D spirals of ``bench_generate.py`` (m = 8,000,000
   codebook states): the time per drawn path of 1,000 time stamps, to show
   that the cost follows the seen states, not m.

Run: ``PYTHONPATH=src .venv/bin/python benchmarks/bench_sample.py`` (about
half a minute). Prints its numbers.
"""

from __future__ import annotations

import numpy as np

from bench_continue import best_of
from bench_generate import spiral_demos
from ndlfd import KeypointHMM, hmm
from ndlfd.synth import obstacle


def main():
    model = KeypointHMM().fit(obstacle(9, 3))
    t = np.linspace(0.0, 5.0, 400)
    model.sample(t, 2, random_state=0)  # compile and cache the routes
    per = best_of(lambda: model.sample(t, 20, random_state=1)) / 20
    print(f"two routes: {per * 1e3:.2f} ms per drawn path of 400 time stamps")
    bins = np.arange(model.n_time_bins)
    seg = model.segment_model_
    sk = best_of(lambda: hmm.sample_paths(seg, bins, 400, random_state=1))
    print(f"two routes: {sk * 1e3:.2f} ms for 400 skeletons (FFBS, 50 bins)")
    paths = model.sample(t, 200, random_state=0)
    up = np.mean([p.get("position")[200, 1] > 0 for p in paths])
    print(f"two routes: major route in {up:.1%} of 200 draws (9 of 12 demos)")

    spiral = KeypointHMM(levels={"position": 20, "velocity": 10}).fit(spiral_demos())
    ts = np.linspace(0.0, 1.0, 1000)
    spiral.sample(ts, 2, random_state=0)
    per = best_of(lambda: spiral.sample(ts, 5, random_state=1), repeat=3) / 5
    print(
        f"spirals (m = {spiral.codebook_.n_states:,}, {spiral.n_states_used_:,}"
        f" seen): {per * 1e3:.2f} ms per drawn path of 1,000 time stamps"
    )


if __name__ == "__main__":
    main()
