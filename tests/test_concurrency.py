"""One fitted model used from several threads at once gives what serial calls give.

8 threads, each making the same 200 mixed calls (generate with and without
start, goal, via and band; key points; sample with a seed) in its own order,
on one fitted model whose caches they fill together.
"""

import threading

import numpy as np
import pytest

from ndlfd import KeypointHMM, synth


def _calls(test, rng, n, generation):
    """``n`` mixed calls: timing only, start, goal, both, band, key points, and
    (blend) a via point and ``sample`` with a seed."""
    P = test.get("position")
    kinds = 8 if generation == "blend" else 6
    calls = []
    for _ in range(n):
        k = int(rng.integers(0, kinds))
        kw: dict = {"dense": bool(k != 5)}
        if k in (1, 3):
            kw["start"] = {"position": P[0] + rng.normal(0.0, 0.3, P.shape[1])}
        if k in (2, 3):
            kw["goal"] = {"position": P[-1] + rng.normal(0.0, 0.3, P.shape[1])}
        if k == 4 and generation == "blend":
            kw["return_std"] = True
        m = int(rng.integers(20, test.n_samples + 1))
        t = np.sort(rng.choice(test.t, m, replace=False))
        if k == 6:
            mid = m // 2
            kw["via"] = [(t[mid], {"position": P[mid] + rng.normal(0.0, 0.1, 2)})]
        if k == 7:
            kw = {"n_samples": 2, "random_state": int(rng.integers(1000))}
        calls.append((t, kw))
    return calls


def _call(model, t, kw):
    if "n_samples" in kw:
        return model.sample(t, **kw)
    return model.generate(t, **kw)


def _arrays(out):
    if isinstance(out, list):  # sampled paths
        return tuple(a for path in out for a in (path.t, path.X))
    if isinstance(out, tuple):
        path, std = out
        return (path.t, path.X, std)
    return (out.t, out.X)


@pytest.mark.parametrize("generation", ["blend", "paper"])
def test_concurrent_generate_equals_serial(generation):
    train, test = synth.make_dataset("square", n_demos=12, random_state=0)
    kw = dict(epsilon=0.1, n_time_bins=30, generation=generation, n_jobs=2)
    calls = _calls(test, np.random.default_rng(1), 200, generation)
    # the reference: the same calls made one after another on another fit
    ref = KeypointHMM(**kw).fit(train)
    serial = [_arrays(_call(ref, t, c)) for t, c in calls]
    model = KeypointHMM(**kw).fit(train)  # fresh: its caches are filled by the threads
    results: dict = {}
    errors: list = []
    barrier = threading.Barrier(8)

    def worker(w):
        order = np.random.default_rng(100 + w).permutation(len(calls))
        try:
            barrier.wait()
            results[w] = {i: _arrays(_call(model, *calls[i])) for i in order}
        except Exception as exc:
            errors.append(exc)

    threads = [threading.Thread(target=worker, args=(w,)) for w in range(8)]
    for th in threads:
        th.start()
    for th in threads:
        th.join(timeout=300)
    assert not errors, errors
    assert len(results) == 8
    for got in results.values():
        for i, expected in enumerate(serial):
            for a, b in zip(got[i], expected, strict=True):
                np.testing.assert_array_equal(a, b)
