"""Continuing an execution and via points: time per call at LASA size.

Every LASA shape of :func:`ndlfd.datasets.lasa_names` (7 demonstrations of
1,000 samples; the default model fitted on the first 6, the 7th held out):
after one warm-up call, the time of ``generate(t, observed=prefix)`` with the
first 30 % of the held-out demonstration observed (best of 7), of
``generate(t, dense=True, via=...)`` through the held-out position at its
middle sample, and the jump at the junction (largest of |step after the
prefix| - |largest step of the prefix|, over the range). Target (issue 17):
``observed`` <= 5 ms, jump <= 0.5 % of the range.

Also, as a robot replanning during one execution: 20 calls on each held-out
demonstration with the prefix growing from 10 % to 50 % of its samples, the
median and the largest time per call over all shapes (the first call after
the fit, which finds the routes and fills the model's cache, apart); and the
same prefix calls on a model with 100 position levels (m = 1,000,000 states
instead of 40,000) on the first 5 shapes, to show the cost follows the seen
states, not the codebook; and, for the prefix's forward filter
(:mod:`ndlfd.learner._filtering`), the same calls with a constant extra
channel learned at 1,000 levels: the same seen states in a codebook 1,000
times as large (m = 40,000,000).

Run: ``PYTHONPATH=src .venv/bin/python benchmarks/bench_continue.py`` (about a
minute). Prints the medians over the shapes.
"""

from __future__ import annotations

import functools
import time

import numpy as np

from ndlfd import Demonstration, KeypointHMM
from ndlfd.datasets import lasa_names, load_lasa


def best_of(f, repeat=7):
    times = []
    for _ in range(repeat):
        t0 = time.perf_counter()
        f()
        times.append(time.perf_counter() - t0)
    return min(times)


def prefix_of(test, n):
    return Demonstration(test.t[:n], test.X[:n], test.columns, test.groups)


def widen(demo):
    """The demonstration with a constant extra channel (one level is ever seen)."""
    X = np.column_stack([demo.X, np.zeros(demo.t.size)])
    return Demonstration(demo.t, X, (*demo.columns, "c"), (*demo.groups, "extra"))


def replanning(model, test, calls=20):
    """Time of each call, the prefix growing from 10 % to 50 % of the samples."""
    out = []
    for n in np.linspace(0.1 * test.t.size, 0.5 * test.t.size, calls).astype(int):
        prefix = prefix_of(test, n)
        t0 = time.perf_counter()
        model.generate(test.t, observed=prefix)
        out.append(time.perf_counter() - t0)
    return out


def main():
    warm = load_lasa(lasa_names()[0])  # compile (or load) the numba kernels once
    KeypointHMM().fit(warm[:-1]).generate(warm[-1].t, observed=prefix_of(warm[-1], 300))
    obs_ms, via_ms, jumps, via_err, replan_ms, first_ms = [], [], [], [], [], []
    for name in lasa_names():
        demos = load_lasa(name)
        train, test = demos[:-1], demos[-1]
        model = KeypointHMM().fit(train)
        first, *later = replanning(model, test)
        first_ms.append(first * 1e3)
        replan_ms += [s * 1e3 for s in later]
        t, P = test.t, test.get("position")
        n = int(0.3 * t.size)
        prefix = Demonstration(t[:n], test.X[:n], test.columns, test.groups)
        model.generate(t, observed=prefix)  # warm-up: routes, segment paths
        call = functools.partial(model.generate, t, observed=prefix)
        obs_ms.append(best_of(call) * 1e3)
        path = model.generate(t, observed=prefix).get("position")
        rng = np.ptp(np.vstack([d.get("position") for d in train]), axis=0)
        step = np.abs(np.diff(P[:n], axis=0)).max(axis=0)
        jumps.append(float(np.max((np.abs(path[n] - path[n - 1]) - step) / rng)))
        via = [(t[t.size // 2], {"position": P[t.size // 2]})]
        model.generate(t, dense=True, via=via)
        call = functools.partial(model.generate, t, dense=True, via=via)
        via_ms.append(best_of(call) * 1e3)
        got = model.generate(t, dense=True, via=via).get("position")[t.size // 2]
        via_err.append(float(np.max(np.abs(got - P[t.size // 2]) / rng)))
    print(f"{len(obs_ms)} LASA shapes, 1,000 samples, 6 training demonstrations")
    print(f"generate(observed=30 % prefix): median {np.median(obs_ms):.2f} ms,"
          f" max {np.max(obs_ms):.2f} ms")  # fmt: skip
    print(f"jump after the prefix: max {max(jumps) * 100:.3f} % of the range")
    print(f"generate(via=middle sample): median {np.median(via_ms):.2f} ms;"
          f" via error max {max(via_err) * 100:.2e} % of the range")  # fmt: skip
    med, top = np.median(replan_ms), np.max(replan_ms)
    f_med, f_top = np.median(first_ms), np.max(first_ms)
    print(f"replanning (20 calls per shape, prefix 10 % -> 50 %): calls 2-20"
          f" median {med:.2f} ms, max {top:.2f} ms; the first after the fit"
          f" median {f_med:.2f} ms, max {f_top:.2f} ms")  # fmt: skip
    coarse, fine = [], []
    for name in lasa_names()[:5]:
        demos = load_lasa(name)
        train, test = demos[:-1], demos[-1]
        prefix = prefix_of(test, int(0.3 * test.t.size))
        for levels, out in ((20, coarse), (100, fine)):
            model = KeypointHMM(levels={"position": levels}).fit(train)
            model.generate(test.t, observed=prefix)
            call = functools.partial(model.generate, test.t, observed=prefix)
            out.append(best_of(call) * 1e3)
    print(f"first 5 shapes, generate(observed=30 %): median {np.median(coarse):.2f} ms"
          f" at 20 position levels (m = 40,000), {np.median(fine):.2f} ms at 100"
          " (m = 1,000,000)")  # fmt: skip
    same, wide, seen = [], [], []
    groups = ("position", "velocity", "extra")
    for name in lasa_names()[:5]:
        demos = load_lasa(name)
        for widened, out in ((False, same), (True, wide)):
            data = [widen(d) for d in demos] if widened else demos
            kw = {"groups": groups, "levels": {"extra": 1000}} if widened else {}
            model = KeypointHMM(**kw).fit(data[:-1])
            prefix = prefix_of(data[-1], int(0.3 * data[-1].t.size))
            model.generate(data[-1].t, observed=prefix)
            call = functools.partial(model.generate, data[-1].t, observed=prefix)
            out.append(best_of(call) * 1e3)
            seen.append(model.n_states_used_)
    assert seen[0::2] == seen[1::2]  # the same seen states
    print(f"first 5 shapes, the same seen states: generate(observed=30 %) median"
          f" {np.median(same):.2f} ms (m = 40,000), {np.median(wide):.2f} ms with"
          " a constant channel at 1,000 levels (m = 40,000,000)")  # fmt: skip


if __name__ == "__main__":
    main()
