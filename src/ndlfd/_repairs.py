"""Repairs of recorded data: one warning each, or one summary per fit.

Reading recorded data repairs small faults: quaternions logged with a few
decimals are renormalized, a velocity of jittery time stamps is fitted over a
window, a bag's repeated stamps and (on request) rows with NaN or inf are
dropped. Alone, each repair gives one :class:`~ndlfd.NdlfdWarning`
(:func:`repaired`). Inside :func:`collecting_repairs` (as each fit's map
steps run, in whichever thread, process or Dask worker) the repairs are
recorded instead, and :func:`summary_warnings` gives one warning per kind of
repair, naming the files and counts.

Examples
--------
>>> import warnings
>>> with collecting_repairs() as log:
...     repaired("rows", 3, "dropped 3 rows")
>>> log
[('rows', 3, None)]
>>> with warnings.catch_warnings(record=True) as caught:
...     warnings.simplefilter("always")
...     summary_warnings([("rows", "a.csv", 3), ("rows", "b.csv", 1)])
>>> print(caught[0].message)
dropped 4 row(s) with NaN or inf (bad_rows='drop') in 2 files: a.csv (3), b.csv (1)
"""

from __future__ import annotations

import threading
import warnings
from contextlib import contextmanager

from ._errors import NdlfdWarning

__all__ = [
    "REPAIRS",
    "SHOWN_FILES",
    "Measured",
    "collecting_repairs",
    "repaired",
    "summary_warnings",
]

#: The kinds of repair and how their summary starts (``{count}``: the total).
REPAIRS = {
    "quaternions": (
        "renormalized {count} quaternion(s) whose norm was off by up to {worst}"
        " (up to 1e-3 is repaired)"
    ),
    "jitter": (
        "time stamps are jittery: velocity is derived by a local straight-line fit"
        " over a time window, not from neighbouring samples,"
    ),
    "stamps": (
        "dropped {count} message(s) whose time stamp repeats an earlier one (kept"
        " the first of each)"
    ),
    "rows": "dropped {count} row(s) with NaN or inf (bad_rows='drop')",
    "files": "skipped {count} file(s) that cannot be read (bad_files='skip'),",
    "left_out": (
        "left out {count} commanded column(s) (goal_, desired_, cmd_, target_ ...)"
        " beside the measured ones they command; map them with groups/--group to"
        " learn them instead,"
    ),
}

#: The kinds whose summary names the sources without a count.
_NAMES_ONLY = ("jitter", "files", "left_out")

#: How many files a summary names before "and N more".
SHOWN_FILES = 5

_local = threading.local()


class Measured(str):
    """A kind of repair that carries its largest measure (how far off).

    It is the kind's name as far as any code that groups or sorts the
    records goes (equal to it, the same hash), and travels with them
    through threads, processes and Dask workers (it pickles with its
    measure); :func:`summary_warnings` gives the largest of a kind.

    Examples
    --------
    >>> k = Measured("quaternions", 4.8e-06)
    >>> k == "quaternions", k.worst
    (True, 4.8e-06)
    """

    worst: float

    def __new__(cls, kind: str, worst: float):
        self = super().__new__(cls, kind)
        self.worst = float(worst)
        return self

    def __reduce__(self):
        return (Measured, (str(self), self.worst))


@contextmanager
def collecting_repairs():
    """Record the repairs made in this thread instead of warning.

    Yields
    ------
    log : list of (str, int, str or None)
        Each repair's kind (a key of :data:`REPAIRS`), count and detail.
    """
    outer = getattr(_local, "log", None)
    log: list[tuple[str, int, str | None]] = []
    _local.log = log
    try:
        yield log
    finally:
        _local.log = outer


def repaired(
    kind: str,
    count: int,
    message: str,
    *,
    detail=None,
    worst: float | None = None,
    stacklevel: int = 2,
) -> None:
    """Report a repair: recorded inside :func:`collecting_repairs`, else a warning.

    Parameters
    ----------
    kind : str
        A key of :data:`REPAIRS`.
    count : int
        How many things were repaired (quaternions, rows, ...).
    message : str
        The warning given outside :func:`collecting_repairs`.
    detail : str, optional
        What the summary says of this source instead of its name and count
        (a skipped file: why).
    worst : float, optional
        The largest measure of the repair (how far a quaternion's norm was
        off): the summary gives the largest over every source.
    stacklevel : int, default=2
        As for :func:`warnings.warn`, from the caller of this function.
    """
    log = getattr(_local, "log", None)
    if log is None:
        warnings.warn(message, NdlfdWarning, stacklevel=stacklevel + 1)
    else:
        log.append(
            (kind if worst is None else Measured(kind, worst), int(count), detail)
        )


def summary_warnings(records, *, stacklevel: int = 2) -> None:
    """One :class:`~ndlfd.NdlfdWarning` per kind of repair, naming the files.

    Parameters
    ----------
    records : iterable of (str, str, int)
        Kind, source (a file, ``demos[i]``) and count, at most one per kind
        and source, in the order to name them.
    stacklevel : int, default=2
        As for :func:`warnings.warn`.
    """
    kinds: dict[str, list[tuple[str, int]]] = {}
    worst: dict[str, float] = {}
    for kind, source, count in records:
        kinds.setdefault(kind, []).append((source, count))
        if isinstance(kind, Measured):
            worst[kind] = max(worst.get(kind, 0.0), kind.worst)
    for kind in REPAIRS:
        if kind not in kinds:
            continue
        items = kinds[kind]
        shown = [s if kind in _NAMES_ONLY else f"{s} ({n})" for s, n in items]
        more = len(shown) - SHOWN_FILES
        sep = "; " if kind == "files" else ", "
        named = sep.join(shown[:SHOWN_FILES]) + (
            f" and {more} more" if more > 0 else ""
        )
        head = REPAIRS[kind].format(
            count=sum(n for _, n in items),
            worst=f"{worst[kind]:.2g}" if kind in worst else "1e-3",
        )
        noun = "file" if len(items) == 1 else "files"
        warnings.warn(
            f"{head} in {len(items)} {noun}: {named}",
            NdlfdWarning,
            stacklevel=stacklevel + 1,
        )
