"""Which KeypointHMM defaults: a sweep of settings on held-out LASA.

Each setting is one generator of :func:`ndlfd.evaluate` (leave one
demonstration out, the 26 single-pattern shapes, both protocols); the table
gives the DTW median (per shape range) of each, its ratio to the default and
to the time-aligned mean of the demonstrations measured in the same run.

Run: ``.venv/bin/python benchmarks/sweep_defaults.py`` (a few minutes on 2
cores). Prints a Markdown table for docs/evaluation.md.
"""

from __future__ import annotations

import functools
import time

import numpy as np

SETTINGS = {
    "default": {},
    "n_time_bins=20": {"n_time_bins": 20},
    "n_time_bins=100": {"n_time_bins": 100},
    "epsilon=0.01": {"epsilon": 0.01},
    "epsilon=0.1": {"epsilon": 0.1},
    "levels 50 (all groups)": {"levels": 50},
    "levels position 100, velocity 20": {"levels": {"position": 100, "velocity": 20}},
    "normalization per-dimension": {"normalization": "per-dimension"},
    "groups position only": {"groups": ("position",)},
    "decoder map": {"decoder": "map"},
    "generation paper": {"generation": "paper"},
}


def main() -> None:
    from ndlfd import evaluate
    from ndlfd.baselines import KeypointHMMGenerator, MeanBaseline
    from ndlfd.datasets import lasa_names

    shapes = [s for s in lasa_names() if not s.startswith("Multi_Models")]
    gens = {
        k: functools.partial(KeypointHMMGenerator, **v) for k, v in SETTINGS.items()
    }
    gens["mean"] = MeanBaseline
    t0 = time.perf_counter()
    res = evaluate(shapes, generators=gens, n_jobs=2, progress=True)
    med = {}
    for r in res.rows:
        if r["ok"]:
            med.setdefault((r["protocol"], r["generator"]), []).append(r["dtw"])
    med = {k: float(np.median(v)) for k, v in med.items()}
    print(
        f"{len(shapes)} single-pattern shapes x 7 folds,"
        f" {time.perf_counter() - t0:.0f} s; failed folds: {len(res.failures)}\n"
    )
    print(
        "| setting | time: DTW median | / default | / mean"
        " | time + start: DTW median | / default | / mean |"
    )
    print("|---|---:|---:|---:|---:|---:|---:|")
    for name in [*SETTINGS, "mean"]:
        cells = []
        for proto in ("time", "time+start"):
            v = med[(proto, name)]
            cells += [
                f"{v:.5f}",
                f"{v / med[(proto, 'default')]:.3f}",
                f"{v / med[(proto, 'mean')]:.3f}",
            ]
        print(f"| {name} | " + " | ".join(cells) + " |")


if __name__ == "__main__":
    main()
