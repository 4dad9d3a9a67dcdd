r"""Map and reduce over chunks of work units: serial, threads, processes or Dask.

:func:`map_reduce` runs ``fn(spec, chunk)`` over chunks of an iterable of work
units and merges the results (objects with ``merge``) as they come, pairwise
in a tree, so at most a few chunks per worker are ever in flight:

==============  ==============================================================
where           when
==============  ==============================================================
this thread     ``n_jobs=1``
threads         ``backend="threads"``: work whose kernels release the GIL
processes       ``backend="processes"``: work that is mostly Python (holds the
                GIL); a persistent pool, the spec and chunks pickled to it
Dask            ``client``: tasks on a cluster, merged on the workers
==============  ==============================================================

Worker processes start with ``fork`` where it is safe (Linux, Python before
3.12) and ``spawn`` otherwise; a ``spawn``\ ed worker imports the caller's
main module, so a script must guard its entry point with
``if __name__ == "__main__":`` (the error says so when it does not).
"""

from __future__ import annotations

import multiprocessing
import os
import sys
import threading
import warnings
from collections import deque
from collections.abc import Callable, Iterable, Iterator
from concurrent.futures import ProcessPoolExecutor, ThreadPoolExecutor
from concurrent.futures.process import BrokenProcessPool
from contextlib import contextmanager

from ._errors import MissingExtraError, ParallelError, ValidationError
from ._registry import Registry

__all__ = [
    "BACKENDS",
    "check_client",
    "keep_workers",
    "map_reduce",
    "progress_bar",
    "shutdown",
    "thread_pool",
]


class _Tree:
    """Merge results as they come, pairwise by level (a binary-counter tree)."""

    def __init__(self) -> None:
        self._stack: list[tuple[int, object]] = []

    def push(self, item) -> None:
        level = 0
        while self._stack and self._stack[-1][0] == level:
            _, other = self._stack.pop()
            item = other.merge(item)
            level += 1
        self._stack.append((level, item))

    def result(self):
        if not self._stack:
            return None
        items = [x for _, x in self._stack]
        return items[0].merge(*items[1:]) if len(items) > 1 else items[0]


def _chunks(units: Iterable, size: int) -> Iterator[list]:
    chunk = []
    for u in units:
        chunk.append(u)
        if len(chunk) >= size:
            yield chunk
            chunk = []
    if chunk:
        yield chunk


class _NoBar:
    def __enter__(self):
        return self

    def __exit__(self, *exc) -> None:
        return None

    def update(self, n: int) -> None:
        return None


def progress_bar(progress, total, desc: str):
    """A tqdm bar: always (True), never (False), or on a terminal after 1 s (None)."""
    if progress is False or (progress is None and not _stderr_is_terminal()):
        return _NoBar()
    from tqdm import tqdm

    delay = 1.0 if progress is None else 0.0
    return tqdm(total=total, desc=desc, unit="demo", leave=False, delay=delay)


def _stderr_is_terminal() -> bool:
    try:
        return sys.stderr.isatty()
    except (AttributeError, ValueError):
        return False


def require_distributed():
    """Import :mod:`distributed` or say how to install it."""
    try:
        import distributed
    except ImportError:
        raise MissingExtraError(
            "fitting on Dask needs dask and distributed; install them with: pip"
            ' install "ndlfd[dask]"'
        ) from None
    return distributed


def check_client(client):
    """A :class:`distributed.Client` (``True``: the current default client)."""
    distributed = require_distributed()
    if client is True:
        try:
            return distributed.get_client()
        except ValueError:
            raise ValidationError(
                "client=True uses the running Dask client, but there is none;"
                " start one with distributed.Client(...) or pass it"
            ) from None
    if not isinstance(client, distributed.Client):
        raise ValidationError(
            "client must be a distributed.Client (or True); got"
            f" {type(client).__name__}"
        )
    return client


def map_reduce(
    fn: Callable,
    spec,
    units: Iterable,
    *,
    total: int | None = None,
    n_jobs: int | None = None,
    backend: str = "threads",
    client=None,
    progress=None,
    desc: str = "",
    chunk_size: int | None = None,
):
    """``fn(spec, chunk)`` over chunks of work units, results merged exactly.

    Parameters
    ----------
    fn : callable
        A module-level function ``(spec, list of units) -> stats`` where
        ``stats`` has ``merge``. It must not submit to the thread pool.
    spec : object
        Passed to every call (pickled with each chunk to worker processes,
        sent once to the Dask cluster).
    units : iterable
        The work units, consumed once and lazily in this thread: at most a few
        chunks per worker are in flight, so an out-of-core source is never
        held whole.
    total : int, optional
        Number of units, for the progress bar and the chunk size.
    n_jobs : int, optional
        Local workers (``None``: one per CPU). Ignored with ``client``.
    backend : {"threads", "processes"}, default="threads"
        What the local workers are (see :data:`BACKENDS`); with one worker
        the chunks run in this thread.
    client : distributed.Client, optional
        Run the chunks as Dask tasks and merge them on the workers (a tree
        reduction); only the result comes back.
    progress : bool or None
        See :func:`progress_bar`.
    desc : str
        Progress bar label.
    chunk_size : int, optional
        Units per task; by default about four tasks per worker, at most 256
        units (64 locally).

    Returns
    -------
    stats
        The merged result, or None if there were no units.

    Raises
    ------
    NdlfdError
        The first error of a chunk, as raised there (pending chunks are
        cancelled).
    ParallelError
        A worker process died (killed, out of memory, or an unguarded script
        under ``spawn``).
    """
    run_local = BACKENDS.get(backend)
    if client is not None:
        workers = max(sum(client.nthreads().values()), 1)
        cap = 256
    else:
        workers = n_jobs if n_jobs is not None else (os.cpu_count() or 1)
        cap = 64
    if chunk_size is None and workers <= 1:
        chunk_size = cap  # serial: no balancing needed, fewest merges
    elif chunk_size is None:
        chunk_size = cap if total is None else -(-total // (4 * workers))
        chunk_size = int(min(max(chunk_size, 1), cap))
    chunks = _chunks(units, chunk_size)
    with progress_bar(progress, total, desc) as bar:
        if client is not None:
            return _run_dask(fn, spec, chunks, client, workers, bar)
        if workers <= 1:
            return _run_serial(fn, spec, chunks, bar)
        return run_local(fn, spec, chunks, workers, bar)


def _run_serial(fn, spec, chunks, bar):
    tree = _Tree()
    for chunk in chunks:
        n = len(chunk)
        tree.push(fn(spec, chunk))
        del chunk  # not held while the next chunk is read
        bar.update(n)
    return tree.result()


def _run_pool(submit, chunks, workers, bar, unpack=lambda r: r):
    """Chunks on an executor, at most two per worker in flight, merged in order."""
    tree = _Tree()
    window: deque = deque()
    try:
        for chunk in chunks:
            window.append((submit(chunk), len(chunk)))
            while len(window) >= 2 * workers:
                fut, n = window.popleft()
                tree.push(unpack(fut.result()))
                bar.update(n)
        while window:
            fut, n = window.popleft()
            tree.push(unpack(fut.result()))
            bar.update(n)
    finally:
        for fut, _ in window:
            fut.cancel()
    return tree.result()


def _run_threads(fn, spec, chunks, workers, bar):
    pool = thread_pool(workers)
    return _run_pool(lambda c: pool.submit(fn, spec, c), chunks, workers, bar)


def _recording(fn, spec, chunk):
    """``fn(spec, chunk)`` and every warning it gave.

    All are recorded: the caller's filters (which a persistent worker does not
    share) decide in :func:`_rewarn` what to show, ignore or raise.
    """
    with warnings.catch_warnings(record=True) as caught:
        warnings.simplefilter("always")
        result = fn(spec, chunk)
    return result, [w.message for w in caught]


def _rewarn(pair):
    """The result of :func:`_recording`, its warnings given again here."""
    result, messages = pair
    for message in messages:
        warnings.warn(message, stacklevel=2)
    return result


def _run_processes(fn, spec, chunks, workers, bar):
    if multiprocessing.current_process().daemon:
        # a daemonic process (a Dask or multiprocessing.Pool worker) may not
        # start processes of its own
        return _run_threads(fn, spec, chunks, workers, bar)
    pool = _process_pool(workers)

    def submit(chunk):
        return pool.submit(_recording, fn, spec, chunk)

    try:
        return _run_pool(submit, chunks, workers, bar, unpack=_rewarn)
    except BrokenProcessPool as exc:
        _drop_process_pool(pool)
        raise ParallelError(
            f"a worker process of the {workers} ended unexpectedly ({exc}). It"
            " may have run out of memory or been killed. Under the"
            f" {pool._mp_context.get_start_method()!r} start method a script"
            " that fits with n_jobs > 1 must guard its entry point with"
            ' if __name__ == "__main__":. Fit with n_jobs=1 to run in this'
            " process."
        ) from None


#: The local ``backend`` choices of :func:`map_reduce`.
BACKENDS = Registry("backend")
BACKENDS.add("threads", _run_threads)
BACKENDS.add("processes", _run_processes)


def start_method() -> str:
    """``"fork"`` where it is safe and available, else ``"spawn"``.

    ``fork`` starts workers in milliseconds with the compiled kernels
    inherited; from Python 3.12 it warns in a process with threads (numpy's
    BLAS has some), and macOS and Windows lack it or advise against it.
    """
    if sys.platform.startswith("linux") and sys.version_info < (3, 12):
        return "fork"
    return "spawn"


# ------------------------------------------------------------------ the pools
#
# ndlfd owns its worker pools here and nowhere else. They are made on first
# use and kept (starting threads costs milliseconds, processes more), with
# three guarantees:
#
# - fork safety: a forked child (multiprocessing, a DataLoader worker,
#   gunicorn --preload) inherits the parent's pool objects but not their
#   threads or processes; ``os.register_at_fork`` forgets them in the child,
#   which makes its own on first use instead of waiting forever on the
#   parent's;
# - worker processes go away after the fit that started them (unless a
#   :func:`keep_workers` block asks to keep them across fits);
# - :func:`shutdown` ends every pool now (the threads and processes are made
#   again when needed).

_THREAD_POOLS: dict[int, ThreadPoolExecutor] = {}
_PROCESS_POOLS: dict[tuple[int, str], ProcessPoolExecutor] = {}
_LOCK = threading.Lock()
_KEEP = [0]  # depth of keep_workers blocks (any thread)


def _forget_pools_in_child() -> None:
    """After a fork, in the child: the inherited pools have no workers here."""
    global _LOCK
    _LOCK = threading.Lock()  # the parent may have held it while forking
    _THREAD_POOLS.clear()
    _PROCESS_POOLS.clear()
    _KEEP[0] = 0


if hasattr(os, "register_at_fork"):  # not on Windows, which cannot fork
    os.register_at_fork(after_in_child=_forget_pools_in_child)


def thread_pool(workers: int) -> ThreadPoolExecutor:
    """A persistent pool of ``workers`` threads, shared by every caller.

    Its tasks never wait on other tasks of the pool, so callers may share it
    from several threads. A forked child gets a new pool on first use.

    Parameters
    ----------
    workers : int
        Number of threads.

    Returns
    -------
    pool : concurrent.futures.ThreadPoolExecutor

    Examples
    --------
    >>> list(thread_pool(2).map(abs, [-1, 2, -3]))
    [1, 2, 3]
    """
    with _LOCK:
        pool = _THREAD_POOLS.get(workers)
        if pool is None:
            pool = ThreadPoolExecutor(workers, thread_name_prefix="ndlfd-worker")
            _THREAD_POOLS[workers] = pool
        return pool


def _process_pool(workers: int) -> ProcessPoolExecutor:
    """A pool of ``workers`` processes, kept until the fit ends."""
    key = (workers, start_method())
    with _LOCK:
        pool = _PROCESS_POOLS.get(key)
        if pool is None or getattr(pool, "_broken", False):
            ctx = multiprocessing.get_context(key[1])
            pool = ProcessPoolExecutor(workers, mp_context=ctx)
            _PROCESS_POOLS[key] = pool
        return pool


def _drop_process_pool(pool: ProcessPoolExecutor) -> None:
    with _LOCK:
        for k, v in list(_PROCESS_POOLS.items()):
            if v is pool:
                del _PROCESS_POOLS[k]
    pool.shutdown(wait=False, cancel_futures=True)


def shutdown(*, threads: bool = True) -> None:
    """End ndlfd's worker processes (and, by default, its threads) now.

    Nothing else is needed: processes end after each fit on their own, and
    threads are idle between calls. Use it in a long-running service that
    wants every thread gone, or before forking by hand. Pools are made again
    on the next call that needs one.

    Parameters
    ----------
    threads : bool, default=True
        Also end the thread pools (waiting for running tasks).

    Examples
    --------
    >>> shutdown()
    """
    with _LOCK:
        procs = list(_PROCESS_POOLS.values())
        _PROCESS_POOLS.clear()
        pools = list(_THREAD_POOLS.values()) if threads else []
        if threads:
            _THREAD_POOLS.clear()
    for pool in procs:
        pool.shutdown(wait=True, cancel_futures=True)
    for pool in pools:
        pool.shutdown(wait=True)


@contextmanager
def keep_workers():
    """Keep worker processes alive between the fits inside this block.

    By default a fit on worker processes (``n_jobs > 1`` on short
    demonstrations) ends them when it returns, so a long-running process
    does not hold their memory. Inside this block they are kept for the next
    fit, and ended when the outermost block exits.

    Examples
    --------
    >>> with keep_workers():
    ...     pass
    """
    with _LOCK:
        _KEEP[0] += 1
    try:
        yield
    finally:
        with _LOCK:
            _KEEP[0] = max(_KEEP[0] - 1, 0)
        release_workers()


def release_workers() -> None:
    """End the worker processes unless a :func:`keep_workers` block is open."""
    with _LOCK:
        if _KEEP[0] > 0 or not _PROCESS_POOLS:
            return
        procs = list(_PROCESS_POOLS.values())
        _PROCESS_POOLS.clear()
    for pool in procs:
        pool.shutdown(wait=True, cancel_futures=True)


def _run_dask(fn, spec, chunks, client, workers, bar):
    """Chunks as Dask tasks, merged on the workers in a balanced tree.

    Results are merged as they finish, but only with one of the same level (as
    :class:`_Tree` does locally), so each statistic is copied O(log n) times:
    merging every result into one growing total would copy it O(n) times.
    """
    distributed = require_distributed()
    spec_f = client.scatter(spec, broadcast=True, hash=False)
    done = distributed.as_completed()
    sizes: dict = {}
    level: dict = {}
    live: set = set()
    ready: dict[int, object] = {}  # level -> a finished result waiting for a pair

    def settle(fut):
        live.discard(fut)
        if fut.status != "finished":
            fut.result()  # raises the task's error on this side
            raise RuntimeError(f"Dask task {fut.key} ended as {fut.status}")
        bar.update(sizes.pop(fut.key, 0))
        lvl = level.pop(fut.key, 0)
        other = ready.pop(lvl, None)
        if other is None:
            ready[lvl] = fut
            return
        merged = client.submit(_merge_all, other, fut, pure=False)
        level[merged.key] = lvl + 1
        live.add(merged)
        done.add(merged)

    try:
        for chunk in chunks:
            data = client.scatter([chunk], hash=False)[0]
            fut = client.submit(fn, spec_f, data, pure=False)
            del data
            sizes[fut.key] = len(chunk)
            live.add(fut)
            done.add(fut)
            while len(live) >= 2 * workers:
                settle(next(done))
        while live:
            settle(next(done))
        if not ready:
            return None
        rest = [ready[k] for k in sorted(ready)]
        if len(rest) == 1:
            return rest[0].result()
        return client.submit(_merge_all, *rest, pure=False).result()
    finally:
        for fut in (*live, *ready.values()):
            fut.cancel()
        spec_f.cancel()


def _merge_all(first, *others):
    return first.merge(*others)
