"""One fitted model used from several threads at once gives what serial calls give."""

import threading

import numpy as np
import pytest

from ndlfd import KeypointHMM, synth


def _calls(test, rng, n):
    """``n`` mixed generate calls: timing only, start, goal, both, band, key points."""
    P = test.get("position")
    calls = []
    for _ in range(n):
        k = int(rng.integers(0, 6))
        kw: dict = {"dense": bool(k != 5)}
        if k in (1, 3):
            kw["start"] = {"position": P[0] + rng.normal(0.0, 0.3, P.shape[1])}
        if k in (2, 3):
            kw["goal"] = {"position": P[-1] + rng.normal(0.0, 0.3, P.shape[1])}
        if k == 4:
            kw["return_std"] = True
        m = int(rng.integers(20, test.n_samples + 1))
        calls.append((np.sort(rng.choice(test.t, m, replace=False)), kw))
    return calls


def _arrays(out):
    if isinstance(out, tuple):
        path, std = out
        return (path.t, path.X, std)
    return (out.t, out.X)


@pytest.mark.parametrize("generation", ["blend", "paper"])
def test_concurrent_generate_equals_serial(generation):
    train, test = synth.make_dataset("square", n_demos=12, random_state=0)
    kw = dict(epsilon=0.1, n_time_bins=30, generation=generation, n_jobs=2)
    calls = _calls(test, np.random.default_rng(1), 200)
    if generation == "paper":
        calls = [
            (t, {k: v for k, v in c.items() if k != "return_std"}) for t, c in calls
        ]
    serial = [
        _arrays(KeypointHMM(**kw).fit(train).generate(t, **c)) for t, c in calls[:1]
    ]
    model = KeypointHMM(**kw).fit(train)  # fresh: its caches are filled by the threads
    serial = [_arrays(KeypointHMM(**kw).fit(train).generate(t, **c)) for t, c in calls]
    results: dict = {}
    errors: list = []
    barrier = threading.Barrier(8)

    def worker(w):
        order = np.random.default_rng(100 + w).permutation(len(calls))
        try:
            barrier.wait()
            results[w] = {i: _arrays(model.generate(calls[i][0], **calls[i][1]))
                          for i in order}  # fmt: skip
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
