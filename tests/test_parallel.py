"""map_reduce: every unit once, in any backend; errors and dead workers reported."""

import os
import threading

import numpy as np
import pytest

from ndlfd import OptionError, ParallelError, ValidationError
from ndlfd._parallel import BACKENDS, map_reduce, start_method
from ndlfd.learner import RangeStats


def _count_chunk(spec, chunk):
    if any(u == spec for u in chunk):
        raise ValidationError(f"unit {spec} is bad")
    return RangeStats(
        np.zeros(1), np.zeros(1), len(chunk),
        np.array(chunk, dtype=np.int64), np.ones(len(chunk), dtype=np.int64),
    )  # fmt: skip


def _pid_chunk(spec, chunk):
    """RangeStats whose 'samples' count the units run outside the caller."""
    r = _count_chunk(-1, chunk)
    outside = len(chunk) if os.getpid() != spec else 0
    return RangeStats(r.data_min, r.data_max, outside, r.items, r.demos_per_item)


def _die(spec, chunk):
    if spec in chunk:
        os._exit(3)  # as a worker killed by the OOM killer
    return _count_chunk(-1, chunk)


@pytest.mark.parametrize("backend", ["threads", "processes"])
@pytest.mark.parametrize("n_jobs", [1, 3])
@pytest.mark.parametrize("chunk_size", [None, 1, 7])
def test_map_reduce_sees_every_unit_once(backend, n_jobs, chunk_size):
    seen_threads = set()

    def units():
        for i in range(100):
            seen_threads.add(threading.get_ident())
            yield i

    r = map_reduce(_count_chunk, -1, units(), total=100, n_jobs=n_jobs,
                   backend=backend, chunk_size=chunk_size,
                   progress=False)  # fmt: skip
    np.testing.assert_array_equal(r.items, np.arange(100))
    assert r.n_samples == 100
    assert seen_threads == {threading.get_ident()}  # consumed in the caller
    assert map_reduce(_count_chunk, -1, iter(()), n_jobs=n_jobs) is None


def test_processes_run_in_other_processes_and_serial_in_this_one():
    me = os.getpid()
    far = map_reduce(_pid_chunk, me, range(50), n_jobs=2, backend="processes")
    near = map_reduce(_pid_chunk, me, range(50), n_jobs=1, backend="processes")
    assert (far.n_samples, near.n_samples) == (50, 0)
    assert far.n_demos == near.n_demos == 50


@pytest.mark.parametrize("backend", ["threads", "processes"])
@pytest.mark.parametrize("n_jobs", [1, 3])
def test_map_reduce_raises_the_failing_units_error(backend, n_jobs):
    with pytest.raises(ValidationError, match="unit 57 is bad"):
        map_reduce(_count_chunk, 57, range(100), total=100, n_jobs=n_jobs,
                   backend=backend, chunk_size=4, progress=False)  # fmt: skip


def test_a_dead_worker_process_is_a_clear_error_and_the_pool_recovers():
    with pytest.raises(ParallelError, match=r"ended unexpectedly.*n_jobs=1"):
        map_reduce(_die, 33, range(100), n_jobs=2, backend="processes",
                   chunk_size=4)  # fmt: skip
    r = map_reduce(_die, -1, range(100), n_jobs=2, backend="processes")
    np.testing.assert_array_equal(r.items, np.arange(100))


def test_unknown_backend_lists_the_choices():
    with pytest.raises(OptionError, match=r"'processes', 'threads'|'threads'"):
        map_reduce(_count_chunk, -1, range(3), backend="mpi")
    assert set(BACKENDS) == {"threads", "processes"}
    assert start_method() in ("fork", "spawn")


def test_progress_bar_when_asked(capsys):
    map_reduce(_count_chunk, -1, range(10), total=10, n_jobs=1, progress=True,
               desc="counting")  # fmt: skip
    assert "counting" in capsys.readouterr().err
    map_reduce(_count_chunk, -1, range(10), total=10, n_jobs=1, progress=False,
               desc="counting")  # fmt: skip
    assert capsys.readouterr().err == ""


def _warn_chunk(spec, chunk):
    import warnings

    from ndlfd import NdlfdWarning

    warnings.warn(f"chunk of {len(chunk)} in process {os.getpid()}", NdlfdWarning,
                  stacklevel=1)  # fmt: skip
    return _count_chunk(-1, chunk)


def test_warnings_of_worker_processes_are_given_again_here():
    from ndlfd import NdlfdWarning

    with pytest.warns(NdlfdWarning) as caught:
        map_reduce(_warn_chunk, None, range(20), n_jobs=2, backend="processes",
                   chunk_size=5)  # fmt: skip
    texts = {str(w.message) for w in caught}
    assert len(texts) >= 1 and all(t.startswith("chunk of 5") for t in texts)
    assert all(f"process {os.getpid()}" not in t for t in texts)


def test_spawned_workers_give_the_same_result(monkeypatch):
    # what Python 3.12+ and macOS get: fresh interpreters that import ndlfd
    import ndlfd._parallel as _parallel

    monkeypatch.setattr(_parallel, "start_method", lambda: "spawn")
    me = os.getpid()
    r = map_reduce(_pid_chunk, me, range(30), n_jobs=2, backend="processes")
    np.testing.assert_array_equal(r.items, np.arange(30))
    assert r.n_samples == 30  # all of it ran in the spawned processes
    assert (2, "spawn") in _parallel._PROCESS_POOLS  # kept until shutdown


def test_a_daemonic_process_maps_on_threads_instead(monkeypatch):
    import multiprocessing

    monkeypatch.setattr(multiprocessing.current_process(), "daemon", True)
    me = os.getpid()
    r = map_reduce(_pid_chunk, me, range(30), n_jobs=2, backend="processes")
    assert r.n_samples == 0 and r.n_demos == 30  # here, on threads


@pytest.fixture(scope="module")
def dask_client():
    distributed = pytest.importorskip("distributed")
    with (
        distributed.LocalCluster(n_workers=2, processes=False, threads_per_worker=1,
                                 dashboard_address=":0") as cluster,
        distributed.Client(cluster) as client,
    ):  # fmt: skip
        yield client


@pytest.mark.parametrize("chunk_size", [1, 3, 64])
def test_dask_sees_every_unit_once_and_reports_the_failing_one(dask_client, chunk_size):
    # 100 units in 1, 3 or 64 per task: many levels of the merge tree, or one
    r = map_reduce(_count_chunk, -1, range(100), total=100, client=dask_client,
                   chunk_size=chunk_size)  # fmt: skip
    np.testing.assert_array_equal(r.items, np.arange(100))
    assert r.n_samples == 100
    with pytest.raises(ValidationError, match="unit 57 is bad"):
        map_reduce(_count_chunk, 57, range(100), client=dask_client,
                   chunk_size=chunk_size)  # fmt: skip
    assert map_reduce(_count_chunk, -1, [], client=dask_client) is None


# ------------------------------------------------------- after a fork or spawn

_PARENT: dict = {}


def _squares(n=12, seed=0):
    from ndlfd import synth

    return synth.make_dataset("square", n_demos=n, random_state=seed)


def _fit_and_generate_here(_):
    """In a worker: the parent's model (inherited by fork) and a new fit."""
    from ndlfd import KeypointHMM

    train, test = _squares()
    model = KeypointHMM(epsilon=0.1, n_time_bins=30, n_jobs=2).fit(train)
    out = [model.generate(test, dense=True).X]
    if "model" in _PARENT:  # forked: the parent's own model
        out.append(_PARENT["model"].generate(test, dense=True).X)
    return out


@pytest.mark.parametrize("method", ["fork", "forkserver", "spawn"])
def test_workers_started_after_use_fit_and_generate(method):
    # the parent used the thread pool (n_jobs=2 aligns on threads); a forked
    # child inherits the pool object but not its threads, and once waited
    # for them for ever
    import multiprocessing

    from ndlfd import KeypointHMM, _parallel

    train, test = _squares()
    model = KeypointHMM(epsilon=0.1, n_time_bins=30, n_jobs=2).fit(train)
    expected = model.generate(test, dense=True).X
    assert _parallel._THREAD_POOLS, "the parent should hold a thread pool"
    _PARENT["model"] = model
    try:
        ctx = multiprocessing.get_context(method)
        with ctx.Pool(2) as pool:
            results = pool.map_async(_fit_and_generate_here, range(2)).get(120)
    finally:
        _PARENT.clear()
    for out in results:
        assert len(out) == (2 if method == "fork" else 1)
        for X in out:
            np.testing.assert_array_equal(X, expected)


def test_a_fit_on_processes_ends_its_workers():
    from ndlfd import KeypointHMM, _parallel, keep_workers

    train, _ = _squares(n=40)
    kw = dict(epsilon=0.1, n_time_bins=30, n_jobs=2)
    # n_jobs=2 maps short demonstrations on worker processes
    _parallel.shutdown()
    serial = KeypointHMM(**{**kw, "n_jobs": 1}).fit(train)
    model = KeypointHMM(**kw).fit(train)
    assert not _parallel._PROCESS_POOLS  # ended when fit returned
    np.testing.assert_array_equal(model.centroids_, serial.centroids_)
    with keep_workers():
        KeypointHMM(**kw).fit(train)
        pools = dict(_parallel._PROCESS_POOLS)
        assert pools  # kept for the next fit in the block
        KeypointHMM(**kw).fit(train)
        assert dict(_parallel._PROCESS_POOLS) == pools  # the same workers
    assert not _parallel._PROCESS_POOLS
    _parallel.shutdown()
    assert not _parallel._THREAD_POOLS
