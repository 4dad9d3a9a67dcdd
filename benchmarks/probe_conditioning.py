"""How much of a via point or a prefix does a generator use beyond a local shift?

For each LASA shape named on the command line and each of its 7 folds (one
demonstration held out, the others fitted), the DTW/range to the held-out path
of

* *via*: ndlfd's ``generate(t, start=, via=[middle sample])``; ndlfd's
  ``generate(t, start=)`` shifted through the via point as the peers are
  (:func:`ndlfd.baselines.pass_through`); ProMP conditioned on the start and
  the via point;
* *prefix* (first 30 % observed, scored on the rest): ndlfd's
  ``generate(t, observed=)``; ndlfd's time-only path shifted onto the last
  observed sample as the peers are; ProMP conditioned on 10 prefix samples.

Where ndlfd's conditioned path scores like its shifted one, the condition only
chose the route and shifted the path; where ProMP scores far lower, its
conditioning carried the point over the whole motion. Prints the medians over
the folds, one line per shape.

Run: ``PYTHONPATH=src .venv/bin/python benchmarks/probe_conditioning.py
BendedLine heee NShape JShape Multi_Models_1 Sine`` (a minute or two).
"""

from __future__ import annotations

import sys

import numpy as np

from ndlfd.baselines import KeypointHMMGenerator, make_baseline, pass_through
from ndlfd.datasets import load_lasa
from ndlfd.demonstration import unit_time
from ndlfd.metrics import dtw_distance

PREFIX = 300  # 30 % of LASA's 1,000 samples


def fold_scores(demos, fold: int, scale: float) -> list[float]:
    test = demos[fold]
    train = [d for i, d in enumerate(demos) if i != fold]
    P, t = test.get("position"), test.t
    tau, k, n = unit_time(t), t.size // 2, PREFIX
    ndlfd = KeypointHMMGenerator().fit(train)
    promp = make_baseline("promp").fit(train)
    via = [(t[k], P[k])]
    shifted_prefix = pass_through(ndlfd.generate(t), tau, [(n - 1, P[n - 1])])
    paths = [
        (ndlfd.generate(t, start=P[0], via=via), 0),
        (pass_through(ndlfd.generate(t, start=P[0]), tau, [(k, P[k])]), 0),
        (promp.generate(t, start=P[0], via=via), 0),
        (ndlfd.generate(t, observed=P[:n]), n),
        (shifted_prefix, n),
        (promp.generate(t, observed=P[:n]), n),
    ]
    return [dtw_distance(P[f:], B[f:], normalize=True) / scale for B, f in paths]


def main(shapes) -> None:
    for shape in shapes:
        demos = load_lasa(shape)
        P = np.concatenate([d.get("position") for d in demos])
        scale = float(np.linalg.norm(np.ptp(P, axis=0)))
        m = np.median([fold_scores(demos, k, scale) for k in range(7)], axis=0)
        print(
            f"{shape}: via ndlfd {m[0]:.4f}, ndlfd shifted {m[1]:.4f}, promp"
            f" {m[2]:.4f} | prefix ndlfd {m[3]:.4f}, ndlfd shifted {m[4]:.4f},"
            f" promp {m[5]:.4f}",
            flush=True,
        )


if __name__ == "__main__":
    main(sys.argv[1:] or ["BendedLine", "heee", "NShape", "JShape"])
