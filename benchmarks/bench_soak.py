"""Soak: 20,000 mixed ``generate`` calls on one fitted model; memory stays flat.

Run: ``PYTHONPATH=src python benchmarks/bench_soak.py [n_calls]``. Prints the
resident set size (RSS) after a warm-up of 1,000 calls and at the end, and the
growth (target: under 10 MiB).
"""

import sys
import time

import numpy as np

from ndlfd import KeypointHMM, synth


def rss_mib() -> float:
    with open("/proc/self/status") as fh:
        for line in fh:
            if line.startswith("VmRSS:"):
                return int(line.split()[1]) / 1024
    return float("nan")


def calls(test, rng, n):
    """Mixed calls: timing only, start, goal, band (``return_std``)."""
    P = test.get("position")
    for _ in range(n):
        k = int(rng.integers(0, 4))
        kw: dict = {"dense": True}
        if k == 1:
            kw["start"] = {"position": P[0] + rng.normal(0.0, 0.3, P.shape[1])}
        elif k == 2:
            kw["goal"] = {"position": P[-1] + rng.normal(0.0, 0.3, P.shape[1])}
        elif k == 3:
            kw["return_std"] = True
        m = int(rng.integers(20, test.n_samples + 1))
        yield np.sort(rng.choice(test.t, m, replace=False)), kw


def main(n_calls: int = 20_000, warmup: int = 1_000) -> None:
    train, test = synth.make_dataset("square", n_demos=12, random_state=0)
    model = KeypointHMM(epsilon=0.1, n_time_bins=30).fit(train)
    rng = np.random.default_rng(0)
    for t, kw in calls(test, rng, warmup):
        model.generate(t, **kw)
    before = rss_mib()
    t0 = time.perf_counter()
    for t, kw in calls(test, rng, n_calls):
        model.generate(t, **kw)
    seconds = time.perf_counter() - t0
    after = rss_mib()
    print(f"{n_calls} generate calls (timing / start / goal / band) in {seconds:.1f} s")
    print(f"RSS after warm-up {before:.1f} MiB, at the end {after:.1f} MiB,")
    print(f"growth {after - before:+.1f} MiB (target < 10 MiB)")


if __name__ == "__main__":
    main(int(sys.argv[1]) if len(sys.argv) > 1 else 20_000)
