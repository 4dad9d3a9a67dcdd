"""A fitted model's cache: what generation computes once, and the last plans.

Two kinds of entries, in one :class:`ModelCache` per fitted model (a refit
or a load starts a new one):

* **once per model**, by plain ``dict`` access: what depends on the training
  data only (the conditioning kernel widths, the routes, the segment paths,
  the two-valued columns, each route's segment counts and the observation
  noise of a prefix's forward filter). Computing one twice from two threads gives the
  same value, so these need no lock;
* **the last plans' parts**, through :meth:`ModelCache.memo`: a route's
  segment model and its decoded skeleton, and the templates aligned to a
  skeleton (:mod:`ndlfd.learner._generation`). A robot replanning at 10–100 Hz
  asks for the same route again and again; these are kept for the
  :data:`MAX_ENTRIES` keys used last (least recently used first out), so the
  memory stays bounded however many starts, goals or prefixes are asked.

Thread-safe: :meth:`ModelCache.memo` holds a lock while it looks up, stores
and evicts (the value is computed outside it: two threads may compute one
value twice, the same value). Fork-safe: a forked child (whose copy of the
lock may have been held by a thread that does not exist there) makes a new
lock on its first use. Never pickled: a pickled or deep-copied model
carries an empty cache, which fills again on use; no entry is ever written
to a model file. The cached values are read-only arrays and models, so a
cached and an uncached call give the same path bit for bit.
"""

from __future__ import annotations

import contextlib
import os
import threading
from collections import OrderedDict

__all__ = ["MAX_ENTRIES", "ModelCache"]

#: Plan parts (routes, aligned skeletons) kept per model.
MAX_ENTRIES = 32


class ModelCache(dict):
    """The once-per-model values (a ``dict``) and a bounded memo of plan parts.

    Examples
    --------
    >>> cache = ModelCache()
    >>> cache.memo(("a", 1), lambda: 42), cache.memo(("a", 1), lambda: 0)
    (42, 42)
    >>> import pickle
    >>> len(pickle.loads(pickle.dumps(cache)).memos)
    0
    """

    def __init__(self, max_entries: int = MAX_ENTRIES):
        super().__init__()
        self.max_entries = max_entries
        self.memos: OrderedDict = OrderedDict()
        self._lock = threading.Lock()
        self._pid = os.getpid()

    def __reduce__(self):
        """Pickle (and deep-copy) as an empty cache of the same bound."""
        return (type(self), (self.max_entries,))

    @contextlib.contextmanager
    def locked(self):
        """Hold the cache's lock (a new one in a forked child)."""
        if self._pid != os.getpid():  # forked: the parent's lock may be held
            self._lock = threading.Lock()
            self._pid = os.getpid()
        with self._lock:
            yield

    def memo(self, key, make):
        """The value stored under ``key``, made by ``make()`` on a miss.

        Parameters
        ----------
        key : hashable
        make : callable
            ``make() -> value``; called without the lock held.

        Returns
        -------
        value
            The stored value (the most recently used from now on).
        """
        with self.locked():
            if key in self.memos:
                self.memos.move_to_end(key)
                return self.memos[key]
        value = make()
        with self.locked():
            value = self.memos.setdefault(key, value)  # another thread's first
            self.memos.move_to_end(key)
            while len(self.memos) > self.max_entries:
                self.memos.popitem(last=False)
        return value
