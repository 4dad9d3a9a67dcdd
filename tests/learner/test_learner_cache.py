"""The model's cache (ndlfd.learner._cache): same paths, bounded, threads, fork."""

import copy
import multiprocessing
import pickle
from concurrent.futures import ThreadPoolExecutor

import numpy as np
import pytest
from test_learner_routes import obstacle

from ndlfd.demonstration import Demonstration
from ndlfd.learner import KeypointHMM
from ndlfd.learner import _generation as generation
from ndlfd.learner._cache import ModelCache

T = np.linspace(0.0, 5.0, 201)


@pytest.fixture(scope="module")
def two_routes():
    demos = obstacle(9, 3)  # 9 over the bump above, 3 below
    return demos, KeypointHMM().fit(demos)


def _prefix(demo, n):
    """The first ``n`` samples of ``demo`` resampled onto ``T``."""
    tau = (demo.t - demo.t[0]) / (demo.t[-1] - demo.t[0])
    X = np.column_stack([np.interp(T[:n] / T[-1], tau, c) for c in demo.X.T])
    return Demonstration(T[:n], X, demo.columns, demo.groups)


def _calls(demos):
    """Generations that use the route memo: prefixes on both routes, starts."""
    out = []
    for j in (0, 4, 9, 11):  # 9 and 11 on the minor route
        for n in (20, 60):
            out.append({"observed": _prefix(demos[j], n)})
    out.append({"start": {"position": demos[10].get("position")[0] + 0.1}})
    out.append({"goal": {"position": [0.2, -0.1]}})
    return out


def test_a_warm_cache_gives_the_same_paths_as_a_cold_one(two_routes, monkeypatch):
    demos, model = two_routes
    calls = _calls(demos)
    first = [model.generate(T, dense=True, **kw).X for kw in calls]  # fills it
    aligned = []
    real = generation.align_many

    def counted(values, *args):
        aligned.append(len(values))
        return real(values, *args)

    monkeypatch.setattr(generation, "align_many", counted)
    warm = [model.generate(T, dense=True, **kw).X for kw in calls]
    assert aligned == []  # every alignment came from the cache
    for kw, a, b in zip(calls, first, warm, strict=True):
        cold = copy.deepcopy(model).generate(T, dense=True, **kw).X  # empty cache
        np.testing.assert_array_equal(a, cold)
        np.testing.assert_array_equal(b, cold)
    assert sum(aligned) > 0  # the cold copies aligned their templates
    # the minor route's prefixes followed it (its own segment model, memoized)
    mid = [model.generate(T, **kw).get("position")[100, 1] for kw in calls[4:8]]
    assert all(y < -3.0 for y in mid), mid


def test_pickled_and_copied_models_carry_an_empty_cache(two_routes):
    demos, model = two_routes
    model.generate(T, observed=_prefix(demos[0], 30))
    for other in (pickle.loads(pickle.dumps(model)), copy.deepcopy(model)):
        np.testing.assert_array_equal(
            other.generate(T, observed=_prefix(demos[0], 30)).X,
            model.generate(T, observed=_prefix(demos[0], 30)).X,
        )


def test_memo_is_bounded_and_least_recently_used_goes_first():
    cache = ModelCache(max_entries=3)
    made = []
    for k in range(5):
        cache.memo(k, lambda k=k: made.append(k) or k * 10)
    assert list(cache.memos) == [2, 3, 4]
    assert cache.memo(2, lambda: -1) == 20  # a hit, now the most recent
    cache.memo(5, lambda: 50)
    assert list(cache.memos) == [4, 2, 5]
    assert made == [0, 1, 2, 3, 4]
    cache["once"] = 1  # the once-per-model values are plain dict items
    assert pickle.loads(pickle.dumps(cache)) == {} and len(cache.memos) == 3


def test_threads_get_the_serial_paths(two_routes):
    demos, model = two_routes
    calls = _calls(demos) * 3
    fresh = copy.deepcopy(model)
    expected = [fresh.generate(T, dense=True, **kw).X for kw in calls]
    cold = copy.deepcopy(model)
    with ThreadPoolExecutor(4) as pool:
        got = list(pool.map(lambda kw: cold.generate(T, dense=True, **kw).X, calls))
    for a, b in zip(expected, got, strict=True):
        np.testing.assert_array_equal(a, b)


_HELD: dict = {}


def _use_held_cache():
    cache = _HELD["cache"]
    assert cache.memo("x", lambda: 1) == 1  # waits for ever on a copied held lock


def test_a_forked_child_does_not_wait_for_a_lock_held_at_the_fork():
    cache = ModelCache()
    _HELD["cache"] = cache
    ctx = multiprocessing.get_context("fork")
    with cache.locked():  # as another thread of the parent might be
        child = ctx.Process(target=_use_held_cache)
        child.start()
        child.join(timeout=20)
    if child.exitcode is None:  # pragma: no cover - the bug: it hangs
        child.kill()
        child.join()
    assert child.exitcode == 0
