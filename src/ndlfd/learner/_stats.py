"""Sufficient statistics of a KeypointHMM fit, and the map and reduce that make them.

A fit reads every demonstration twice and never needs two of them at once:

=========  ====================================================  ===============
pass       map (one demonstration)                               reduce
=========  ====================================================  ===============
1 ranges   per-column min and max, sample count                  :class:`RangeStats`:
                                                                 min / max, sums
2 counts   normalize, key points, codebook states, time bins,    :class:`FitStats`:
           centroid sums, first and last sample; the full        concatenate by
           values only for a blend template                      demonstration,
                                                                 add sums
=========  ====================================================  ===============

Both reductions are **exact**, so the result does not depend on how the
demonstrations are split into parts or in which order the parts are merged:
min and max are exact, counts are integers, per-demonstration arrays are kept
in demonstration order, and the centroid sums are accumulated as integers (see
:func:`to_limbs`). Serial, threaded and Dask fits therefore give the same
model bit for bit.

The passes are in :mod:`ndlfd.learner._passes`; :func:`ndlfd._parallel.map_reduce`
runs them. The exact sums are in :mod:`ndlfd.learner._exact`, the template
choice in :mod:`ndlfd.learner._templates`.
"""

from __future__ import annotations

from collections import Counter
from collections.abc import Sequence
from dataclasses import dataclass
from typing import NamedTuple

import numpy as np

from .._errors import ModelFormatError, ValidationError
from ..codebook import intern_cells
from ._exact import LIMB_BITS, N_LIMBS, from_limbs, to_limbs
from ._fit_kernels import column_extremes, group_sums
from ._states import cell_problems, cells_of_numbers

__all__ = ["DemoStats", "FitStats", "RangeStats", "merge_repairs"]

# ----------------------------------------------------------------- ragged helpers


def _ragged_take(flat: np.ndarray, counts: np.ndarray, order: np.ndarray):
    """Reorder the runs of a ragged array (run ``j`` has ``counts[j]`` rows)."""
    if order is None:
        return flat
    if order.size == 0:
        return flat[:0]
    starts = np.cumsum(counts) - counts
    c = counts[order]
    new_starts = np.cumsum(c) - c
    idx = np.repeat(starts[order] - new_starts, c) + np.arange(int(c.sum()))
    return flat[idx]


def _group_sum(states, counts, limbs):
    """Sorted distinct states, their summed counts and summed limbs (exact)."""
    order = np.argsort(states, kind="stable")
    s = states[order]
    if s.size == 0:
        return s, counts[:0], limbs[:, :0]
    new = np.empty(s.size, dtype=bool)
    new[0] = True
    np.not_equal(s[1:], s[:-1], out=new[1:])
    starts = np.flatnonzero(new)
    return (
        s[starts],
        np.add.reduceat(counts[order], starts),
        group_sums(limbs, order, starts),  # integers: the same in any order
    )


def _split(flat: np.ndarray, counts: np.ndarray) -> list[np.ndarray]:
    """``np.split(flat, np.cumsum(counts)[:-1])`` (views), without its overhead."""
    ends = np.cumsum(counts).tolist()
    return [flat[a:b] for a, b in zip([0, *ends][:-1], ends, strict=True)]


def _sorted_unique_index(index: np.ndarray, what: str) -> np.ndarray:
    if np.all(index[1:] > index[:-1]):
        return None  # already in order (the usual case): no reordering
    order = np.argsort(index, kind="stable")
    s = index[order]
    dup = np.flatnonzero(s[1:] == s[:-1])
    if dup.size:
        raise ValidationError(
            f"cannot merge statistics that both hold {what} {int(s[dup[0]])};"
            " every demonstration must be counted once"
        )
    return order


def _take(a: np.ndarray, order):
    return a if order is None else a[order]


# ----------------------------------------------------------------- pass 1


def _by_item(note: tuple) -> tuple:
    return note[1], note[0]


@dataclass(frozen=True, eq=False)
class RangeStats:
    """Pass-1 statistics: per-column range and how many demonstrations per item.

    Parameters
    ----------
    data_min, data_max : ndarray of shape (n_dims,)
        Smallest and largest value of each column over the demonstrations.
    n_samples : int
        Rows seen.
    items : ndarray of shape (n_items,), dtype int64
        Indices of the input items (a demonstration or a file) seen, sorted.
    demos_per_item : ndarray of shape (n_items,), dtype int64
        How many demonstrations each item held (a file may hold several).
    min_samples, max_samples : int
        Samples of the shortest and of the longest demonstration.
    shortest_item, longest_item : int
        The item that holds it (the first such item on ties).
    notes : tuple of (str, int, int)
        Distinct notes on the demonstrations (how their files were read),
        each with the first item it came from and how many demonstrations
        had it, in the order of their first items.
    repairs : tuple of (str, int, str, int)
        The repairs of the data made in reading and preparing them (see
        :mod:`ndlfd._repairs`): kind, item, its label (the file) and count, one
        per kind and item, in the order of the items.

    Examples
    --------
    >>> a = RangeStats.of(0, np.array([[0.0, 5.0], [1.0, 4.0]]))
    >>> b = RangeStats.of(1, np.array([[-1.0, 9.0]]))
    >>> ab = a + b
    >>> ab.data_min, ab.data_max, ab.n_samples, ab.n_demos
    (array([-1.,  4.]), array([1., 9.]), 3, 2)
    >>> ab.min_samples, ab.shortest_item, ab.max_samples, ab.longest_item
    (1, 1, 2, 0)
    """

    data_min: np.ndarray
    data_max: np.ndarray
    n_samples: int
    items: np.ndarray
    demos_per_item: np.ndarray
    min_samples: int = 0
    max_samples: int = 0
    shortest_item: int = 0
    longest_item: int = 0
    notes: tuple = ()
    repairs: tuple = ()

    @classmethod
    def of(cls, item: int, *arrays: np.ndarray, notes=(), repairs=()) -> RangeStats:
        """The statistics of the demonstrations (value arrays) of one item.

        ``notes`` holds a note (a string) per demonstration, or nothing;
        ``repairs`` the item's (kind, item, label, count) records.
        """
        return cls.of_items([(item, arrays, notes, repairs)])

    @classmethod
    def of_items(cls, entries) -> RangeStats:
        """:meth:`of` of several items at once: the same as merging theirs.

        Parameters
        ----------
        entries : sequence of (int, sequence of ndarray, sequence, sequence)
            Per item (at least one): its index, the value arrays of its
            demonstrations (at least one), their notes and its repairs, as
            :meth:`of` takes them.

        Returns
        -------
        stats : RangeStats
        """
        ends, notes, short, long = [], [], [], []
        for item, arrays, item_notes, _ in entries:
            if len(arrays) == 1:
                ends.append(column_extremes(arrays[0]))
            else:
                e = [column_extremes(a) for a in arrays]
                lo = np.min([x[0] for x in e], axis=0)
                ends.append((lo, np.max([x[1] for x in e], axis=0)))
            lengths = [a.shape[0] for a in arrays]
            short.append((min(lengths), item))
            long.append((-max(lengths), item))
            if item_notes:
                notes.extend((t, item, c) for t, c in Counter(item_notes).items())
        items = np.array([e[0] for e in entries], dtype=np.int64)
        order = _sorted_unique_index(items, "item")
        per_item = np.array([len(e[1]) for e in entries], dtype=np.int64)
        (min_samples, shortest), (max_samples, longest) = min(short), min(long)
        return cls(
            np.min([e[0] for e in ends], axis=0),
            np.max([e[1] for e in ends], axis=0),
            sum(a.shape[0] for e in entries for a in e[1]),
            _take(items, order),
            _take(per_item, order),
            min_samples,
            -max_samples,
            shortest,
            longest,
            _merged_notes(notes),
            merge_repairs(*(e[3] for e in entries)),
        )

    @property
    def n_demos(self) -> int:
        """Number of demonstrations seen."""
        return int(self.demos_per_item.sum())

    def merge(self, *others: RangeStats) -> RangeStats:
        """The statistics of all demonstrations of ``self`` and ``others``."""
        parts = (self, *others)
        items = np.concatenate([p.items for p in parts])
        order = _sorted_unique_index(items, "item")
        short = min(parts, key=lambda p: (p.min_samples, p.shortest_item))
        long = min(parts, key=lambda p: (-p.max_samples, p.longest_item))
        return RangeStats(
            np.min([p.data_min for p in parts], axis=0),
            np.max([p.data_max for p in parts], axis=0),
            sum(p.n_samples for p in parts),
            _take(items, order),
            _take(np.concatenate([p.demos_per_item for p in parts]), order),
            short.min_samples,
            long.max_samples,
            short.shortest_item,
            long.longest_item,
            _merged_notes(x for p in parts for x in p.notes),
            merge_repairs(*(p.repairs for p in parts)),
        )

    __add__ = merge


def _merged_notes(notes) -> tuple:
    """Notes (text, first item, count), one per text, in the order of first items."""
    seen: dict[str, list[int]] = {}
    for text, first, n in notes:
        got = seen.setdefault(text, [first, 0])
        got[0], got[1] = min(got[0], first), got[1] + n
    return tuple(sorted(((t, f, n) for t, (f, n) in seen.items()), key=_by_item))


def merge_repairs(*groups) -> tuple:
    """Repair records (kind, item, label, count), one per kind and item, sorted.

    The same kind of repair of the same item seen twice (the first item is
    read for the groups, then in pass 1) counts once.
    """
    seen: dict = {}
    for kind, item, label, count in (r for g in groups for r in g):
        seen.setdefault((item, kind), (kind, item, label, count))
    return tuple(seen[k] for k in sorted(seen))


# ----------------------------------------------------------------- pass 2


def _frame_row(r) -> np.ndarray:
    """A demonstration's frame poses as one row (empty without frames)."""
    return np.zeros(0) if r.frames is None else np.asarray(r.frames, np.float64)


class DemoStats(NamedTuple):
    """One demonstration's part of the fit statistics (:meth:`FitStats.of_demos`).

    Attributes
    ----------
    index : int
        The demonstration's index in the training set.
    values : ndarray of shape (n_samples, n_dims)
        Its normalized (unweighted) values.
    tau : ndarray of shape (n_samples,) or None
        Its normalized times (0 to 1); read for a template only.
    keypoints, key_bins : ndarray of shape (n_keys,), dtype int64
        Key-point indices, and the time bin of each.
    key_cells : ndarray of shape (n_keys, n_dims), dtype int64
        The codebook cell of each key point (its level index per column).
    n_clipped : int
        Values the codebook clipped.
    template : bool
        Keep the full values and times (a blend template).
    frames : ndarray of shape (n_frame_values,) or None
        Its task frames' poses, one after another (none: empty).
    """

    index: int
    values: np.ndarray
    tau: np.ndarray | None
    keypoints: np.ndarray
    key_cells: np.ndarray
    key_bins: np.ndarray
    n_clipped: int = 0
    template: bool = False
    frames: np.ndarray | None = None


#: FitStats fields: name → (dtype, kind) where kind says what the first axis
#: runs over: "demo" (one row per demonstration), "key" (one per key point),
#: "state" (one per centroid state), "cells" (one row per state, one column
#: per dim), "template" (one per template),
#: "sample" (one per template sample), "limbs" (3, state, dim), "dim", "scalar".
_FIELDS = {
    "exponents": (np.int64, "dim"),
    "demo_index": (np.int64, "demo"),
    "n_samples": (np.int64, "demo"),
    "n_keys": (np.int64, "demo"),
    "first": (np.float64, "demo"),
    "last": (np.float64, "demo"),
    "frames": (np.float64, "demo"),
    "keypoints": (np.int64, "key"),
    "key_states": (np.int64, "key"),
    "key_bins": (np.int64, "key"),
    "centroid_cells": (np.int64, "cells"),
    "centroid_counts": (np.int64, "state"),
    "centroid_limbs": (np.int64, "limbs"),
    "template_index": (np.int64, "template"),
    "template_counts": (np.int64, "template"),
    "template_values": (np.float64, "sample"),
    "template_tau": (np.float64, "sample"),
    "n_clipped": (np.int64, "scalar"),
}
#: The fields of the templates' full values and times (see ``FitStats``).
_PIECED = ("template_values", "template_tau")


class FitStats:
    """The sufficient statistics of a KeypointHMM fit: small, mergeable, saveable.

    One object holds, for a set of demonstrations (normalized with one fitted
    scaler):

    * per demonstration (in index order): its index, sample count, key-point
      indices, the state and time bin of each key point (the HMM and the
      segment model are estimated from these), and its first and last
      normalized sample (for start and goal conditioning);
    * per state, a codebook cell the key points visit: the cell (its level
      index per column, ``centroid_cells``), the exact sum (as integer limbs,
      :func:`to_limbs`) and count of the normalized key-point values in it
      (the centroids). States are the visited cells interned
      (:func:`ndlfd.codebook.intern_cells`): ids ``0..n_states-1`` in the
      cells' lexicographic order, whatever the number of columns;
    * the full normalized values and normalized times of the demonstrations
      that are blend templates only;
    * the number of values the codebook clipped.

    Its size grows with the number of key points, not of samples (plus the
    templates). :meth:`merge` (or ``+``) is exact, associative and
    commutative; it refuses to count a demonstration twice.
    :meth:`to_arrays` / :meth:`from_arrays` give plain numeric arrays for an
    ``.npz`` file.

    Build one per demonstration with :meth:`of_demo`.

    Examples
    --------
    >>> U = np.array([[0.0, 0.0], [0.5, 0.5], [1.0, 1.0]])
    >>> tau = np.array([0.0, 0.5, 1.0])
    >>> kw = dict(exponents=np.array([0, 0]), n_clipped=0)
    >>> a = FitStats.of_demo(0, U, tau, np.array([0, 2]), np.array([[0, 0], [1, 1]]),
    ...                      np.array([0, 1]), template=True, **kw)
    >>> b = FitStats.of_demo(1, U[::-1], tau, np.array([0, 1, 2]),
    ...                      np.array([[1, 1], [1, 0], [0, 0]]),
    ...                      np.array([0, 0, 1]), template=False, **kw)
    >>> ab = a + b
    >>> ab == b + a, ab.n_demos, ab.template_index
    (True, 2, array([0]))
    >>> ab.centroid_cells.tolist(), ab.key_states  # the visited cells, the ids
    ([[0, 0], [1, 0], [1, 1]], array([0, 2, 2, 1, 0]))
    >>> states, centroids = ab.centroids()
    >>> states, centroids
    (array([0, 1, 2]), array([[0. , 0. ],
           [0.5, 0.5],
           [1. , 1. ]]))
    >>> FitStats.from_arrays(ab.to_arrays()) == ab
    True
    """

    # the templates' values and times are held as one piece per template
    # (``_pieces``) and joined into the flat fields only when those are read
    # (``_joined``): merging never copies them
    __slots__ = (*(k for k in _FIELDS if k not in _PIECED), "_pieces", "_joined")
    __hash__ = None  # mutable arrays inside; compared by value

    def __init__(self, **arrays) -> None:
        missing = set(_FIELDS) - set(arrays)
        extra = set(arrays) - set(_FIELDS)
        if missing or extra:
            raise ValidationError(
                f"FitStats needs exactly the fields {', '.join(_FIELDS)}; missing"
                f" {sorted(missing)}, unexpected {sorted(extra)}"
            )
        for name, (dtype, _) in _FIELDS.items():
            if name not in _PIECED:
                object.__setattr__(self, name, np.asarray(arrays[name], dtype=dtype))
        joined = tuple(np.asarray(arrays[k], dtype=np.float64) for k in _PIECED)
        object.__setattr__(self, "_joined", joined)
        object.__setattr__(self, "_pieces", None)

    @classmethod
    def _of_pieces(cls, pieces, **arrays) -> FitStats:
        """Statistics whose templates are ``(values, tau)`` pieces, one each."""
        d = np.asarray(arrays["exponents"]).size
        out = cls(template_values=np.zeros((0, d)), template_tau=np.zeros(0), **arrays)
        object.__setattr__(out, "_pieces", tuple(pieces))
        object.__setattr__(out, "_joined", None)
        return out

    def _template_pieces(self) -> tuple:
        """``(values, tau)`` of each template, in template order."""
        pieces = self._pieces
        if pieces is None:
            values, tau = self._joined
            counts = self.template_counts
            pieces = tuple(
                zip(_split(values, counts), _split(tau, counts), strict=True)
            )
            object.__setattr__(self, "_pieces", pieces)
        return pieces

    def _joined_templates(self) -> tuple[np.ndarray, np.ndarray]:
        joined = self._joined
        if joined is None:  # the same arrays whichever thread joins them first
            pieces = self._pieces
            if pieces:
                joined = tuple(np.concatenate(a) for a in zip(*pieces, strict=True))
            else:
                joined = (np.zeros((0, self.exponents.size)), np.zeros(0))
            object.__setattr__(self, "_joined", joined)
        return joined

    @property
    def template_values(self) -> np.ndarray:
        """The templates' normalized values, one after another (n_samples, n_dims)."""
        return self._joined_templates()[0]

    @property
    def template_tau(self) -> np.ndarray:
        """The templates' normalized times, one after another (n_samples,)."""
        return self._joined_templates()[1]

    # ------------------------------------------------------------ building
    @classmethod
    def of_demo(
        cls,
        index: int,
        values: np.ndarray,
        tau: np.ndarray,
        keypoints: np.ndarray,
        key_cells: np.ndarray,
        key_bins: np.ndarray,
        *,
        exponents: np.ndarray,
        n_clipped: int,
        template: bool,
    ) -> FitStats:
        """The statistics of one demonstration (:meth:`of_demos` of one).

        Parameters
        ----------
        index, values, tau, keypoints, key_cells, key_bins
            The demonstration, as the fields of :class:`DemoStats`.
        exponents : ndarray of shape (n_dims,)
            Scale exponents of the centroid sums (:func:`scale_exponents`),
            the same for every demonstration of a fit.
        n_clipped, template
            As the fields of :class:`DemoStats`.

        Returns
        -------
        stats : FitStats
        """
        part = DemoStats(
            index, values, tau, keypoints, key_cells, key_bins, n_clipped, template
        )
        return cls.of_demos([part], exponents=exponents)

    @classmethod
    def of_demos(cls, demos: Sequence[DemoStats], *, exponents) -> FitStats:
        """The statistics of several demonstrations at once (a chunk of a pass).

        The same as merging their :meth:`of_demo` (bit for bit), with the
        per-demonstration overhead of one object instead of one each.

        Parameters
        ----------
        demos : sequence of DemoStats
            At least one; each demonstration once.
        exponents : ndarray of shape (n_dims,)
            Scale exponents of the centroid sums.

        Returns
        -------
        stats : FitStats
        """
        if not demos:
            raise ValidationError("of_demos needs at least one demonstration; got none")
        cat = np.concatenate
        values = [np.asarray(r.values, dtype=np.float64) for r in demos]
        keys = [np.asarray(r.keypoints, dtype=np.int64) for r in demos]
        d = np.asarray(exponents).size
        cells = cat(
            [np.asarray(r.key_cells, dtype=np.int64).reshape(-1, d) for r in demos]
        )
        kept = [(r, v) for r, v in zip(demos, values, strict=True) if r.template]
        raw = cls._of_pieces(  # one row per key point in the centroids: merge sums them
            [(v, np.asarray(r.tau, dtype=np.float64)) for r, v in kept],
            exponents=exponents,
            demo_index=[r.index for r in demos],
            n_samples=[v.shape[0] for v in values],
            n_keys=[k.size for k in keys],
            first=cat([v[:1] for v in values]),
            last=cat([v[-1:] for v in values]),
            frames=np.stack([_frame_row(r) for r in demos]),
            keypoints=cat(keys),
            key_states=np.arange(cells.shape[0], dtype=np.int64),  # a cell each
            key_bins=cat([r.key_bins for r in demos]),
            centroid_cells=cells,
            centroid_counts=np.ones(cells.shape[0], dtype=np.int64),
            centroid_limbs=to_limbs(
                cat([v[k] for v, k in zip(values, keys, strict=True)]), exponents
            ),
            template_index=[r.index for r, _ in kept],
            template_counts=[v.shape[0] for _, v in kept],
            n_clipped=sum(int(r.n_clipped) for r in demos),
        )
        return raw.merge()

    # ------------------------------------------------------------ reading
    @property
    def n_demos(self) -> int:
        """Number of demonstrations counted."""
        return int(self.demo_index.size)

    @property
    def n_dims(self) -> int:
        """Number of columns."""
        return int(self.exponents.size)

    def keypoint_lists(self):
        """Per demonstration: key-point indices, key states, key bins (lists)."""
        return (
            _split(self.keypoints, self.n_keys),
            _split(self.key_states, self.n_keys),
            _split(self.key_bins, self.n_keys),
        )

    def templates(self):
        """Per template: normalized values and normalized times (lists)."""
        pieces = self._template_pieces()
        return [v for v, _ in pieces], [t for _, t in pieces]

    @property
    def centroid_states(self) -> np.ndarray:
        """The states' ids, ``0..n_states_seen-1`` (one per visited cell)."""
        return np.arange(self.centroid_counts.size, dtype=np.int64)

    def centroids(self) -> tuple[np.ndarray, np.ndarray]:
        """The states (ids) and the mean normalized key-point value in each.

        Returns
        -------
        states : ndarray of shape (n_states_seen,), dtype int64
            ``0..n_states_seen-1``; state ``i`` is the cell
            ``centroid_cells[i]``.
        centroids : ndarray of shape (n_states_seen, n_dims)
        """
        sums = from_limbs(self.centroid_limbs, self.exponents)
        return self.centroid_states, sums / self.centroid_counts[:, None]

    # ------------------------------------------------------------ merging
    def merge(self, *others: FitStats) -> FitStats:
        """The statistics of the demonstrations of ``self`` and all ``others``.

        Exact: associative and commutative, whatever the grouping.

        Raises
        ------
        ValidationError
            Statistics of other columns or scales, or a demonstration counted
            in two of them.
        """
        parts = (self, *others)
        for k, p in enumerate(parts[1:], start=1):
            if not isinstance(p, FitStats):
                raise ValidationError(
                    f"can only merge FitStats; got {type(p).__name__} at {k}"
                )
            if not np.array_equal(p.exponents, self.exponents):
                raise ValidationError(
                    "cannot merge statistics of different fits (columns or scales"
                    f" differ: {self.exponents.tolist()} and {p.exponents.tolist()})"
                )

        def cat(arrays, axis=0):  # one part (of_demos): its arrays, not a copy
            return arrays[0] if len(arrays) == 1 else np.concatenate(arrays, axis)

        index = cat([p.demo_index for p in parts])
        order = _sorted_unique_index(index, "demonstration")
        n_keys = cat([p.n_keys for p in parts])
        t_index = cat([p.template_index for p in parts])
        t_order = _sorted_unique_index(t_index, "template")
        t_counts = cat([p.template_counts for p in parts])
        pieces = [x for p in parts for x in p._template_pieces()]
        # the parts' cells interned together: each part's ids renumbered
        offsets = np.cumsum([0] + [p.centroid_cells.shape[0] for p in parts])
        cells, renumber = intern_cells(cat([p.centroid_cells for p in parts]))
        key_states = cat(
            [renumber[a + p.key_states] for p, a in zip(parts, offsets, strict=False)]
        )
        _, counts, sums = _group_sum(
            renumber,
            cat([p.centroid_counts for p in parts]),
            cat([p.centroid_limbs for p in parts], axis=1),
        )
        if counts.size and counts.max() >= 2**LIMB_BITS:
            raise ValidationError(
                f"a codebook state holds {int(counts.max())} key points, more than"
                f" the {2**LIMB_BITS} the exact centroid sums allow"
            )
        return FitStats._of_pieces(
            pieces if t_order is None else [pieces[k] for k in t_order],
            exponents=self.exponents,
            demo_index=_take(index, order),
            n_samples=_take(cat([p.n_samples for p in parts]), order),
            n_keys=_take(n_keys, order),
            first=_take(cat([p.first for p in parts]), order),
            last=_take(cat([p.last for p in parts]), order),
            frames=_take(cat([p.frames for p in parts]), order),
            keypoints=_ragged_take(cat([p.keypoints for p in parts]), n_keys, order),
            key_states=_ragged_take(key_states, n_keys, order),
            key_bins=_ragged_take(cat([p.key_bins for p in parts]), n_keys, order),
            centroid_cells=cells,
            centroid_counts=counts,
            centroid_limbs=sums,
            template_index=_take(t_index, t_order),
            template_counts=_take(t_counts, t_order),
            n_clipped=int(sum(int(p.n_clipped) for p in parts)),
        )

    __add__ = merge

    def __eq__(self, other) -> bool:
        if not isinstance(other, FitStats):
            return NotImplemented
        return all(np.array_equal(getattr(self, k), getattr(other, k)) for k in _FIELDS)

    def __repr__(self) -> str:
        return (
            f"FitStats(n_demos={self.n_demos}, n_keys={int(self.n_keys.sum())},"
            f" n_states={self.centroid_counts.size},"
            f" n_templates={self.template_index.size}, n_dims={self.n_dims})"
        )

    # ------------------------------------------------------------ arrays
    def to_arrays(self, prefix: str = "") -> dict[str, np.ndarray]:
        """The statistics as plain numeric arrays (for an ``.npz`` file).

        Parameters
        ----------
        prefix : str, default=""
            Prepended to every key.

        Returns
        -------
        arrays : dict of str to ndarray
        """
        out = {prefix + k: getattr(self, k).copy() for k in _FIELDS}
        if self.frames.shape[1] == 0:  # no task frames: the file as before them
            del out[prefix + "frames"]
        return out

    @classmethod
    def from_arrays(cls, arrays, prefix: str = "", *, levels=None) -> FitStats:
        """Rebuild statistics from :meth:`to_arrays` output, checking every array.

        With ``levels``, statistics of mixed-radix states (model files of
        versions 3, 4) are read into cells (:func:`._states.cells_of_numbers`).

        Parameters
        ----------
        arrays : mapping of str to ndarray
            May hold other keys; only those starting with ``prefix`` are read.
        prefix : str, default=""
        levels : sequence of int, optional
            The codebook's levels: the cells' bounds, checked, and what reads
            mixed-radix states.

        Returns
        -------
        stats : FitStats

        Raises
        ------
        ModelFormatError
            A missing array, a wrong dtype or shape, or arrays that disagree.
        """
        got = {}
        if prefix + "centroid_cells" not in arrays and levels is not None:
            arrays = cells_of_numbers(arrays, prefix, levels)
        for k, (dtype, _) in _FIELDS.items():
            if k == "frames" and prefix + k not in arrays:  # before task frames
                n = np.asarray(arrays.get(prefix + "demo_index", ())).shape[0]
                got[k] = np.zeros((n, 0))
                continue
            if prefix + k not in arrays:
                raise ModelFormatError(f"fit statistics lack the array {prefix + k!r}")
            a = np.asarray(arrays[prefix + k])
            kinds = ("i", "u") if dtype is np.int64 else ("f",)
            if a.dtype.kind not in kinds:
                raise ModelFormatError(
                    f"fit statistics array {prefix + k!r} has dtype {a.dtype};"
                    f" expected {np.dtype(dtype)}"
                )
            got[k] = a.astype(dtype)
        _check_consistent(got)
        if levels is not None:
            cells = got["centroid_cells"]
            if cells.shape[1] != len(levels) or np.any(cells >= np.asarray(levels)):
                raise ModelFormatError(
                    "inconsistent fit statistics (tampered file?): a cell lies"
                    f" outside the codebook's levels {list(levels)}"
                )
        return cls(**got)


def _check_consistent(a: dict) -> None:
    d = a["exponents"].shape[0] if a["exponents"].ndim == 1 else -1
    n = a["demo_index"].shape[0] if a["demo_index"].ndim == 1 else -1
    s = a["centroid_counts"].shape[0] if a["centroid_counts"].ndim == 1 else -1
    t = a["template_index"].shape[0] if a["template_index"].ndim == 1 else -1
    n_key = int(a["n_keys"].sum()) if a["n_keys"].ndim == 1 else -1
    n_smp = int(a["template_counts"].sum()) if a["template_counts"].ndim == 1 else -1
    want = {
        "dim": (d,),
        "demo": (n,),
        "key": (n_key,),
        "state": (s,),
        "template": (t,),
        "sample": (n_smp,),
        "limbs": (N_LIMBS, s, d),
        "cells": (s, d),
        "scalar": (),
    }
    problems = []
    for k, (_, kind) in _FIELDS.items():
        shape = want[kind]
        if k in ("first", "last"):
            shape = (n, d)
        elif k == "frames":
            shape = (n, a[k].shape[1] if a[k].ndim == 2 else -1)
        elif k == "template_values":
            shape = (n_smp, d)
        if min(shape, default=0) < 0 or a[k].shape != shape:
            problems.append(f"{k} has shape {a[k].shape}, expected {shape}")
    if not problems:
        floats = ("first", "last", "frames", "template_values", "template_tau")
        if not all(np.all(np.isfinite(a[k])) for k in floats):
            problems.append("non-finite values")
        if np.any(np.diff(a["demo_index"]) <= 0) or np.any(
            np.diff(a["template_index"]) <= 0
        ):
            problems.append("indices not strictly increasing")
        problems += cell_problems(a["centroid_cells"])
        if np.any(a["centroid_counts"] < 1) or np.any(a["n_keys"] < 1):
            problems.append("empty counts")
        elif int(a["centroid_counts"].sum()) != n_key:
            problems.append("centroid counts do not add up to the key points")
        elif not np.array_equal(np.unique(a["key_states"]), np.arange(s)):
            problems.append("centroid states are not the key points' states")
        starts = np.cumsum(a["n_keys"]) - a["n_keys"]
        k_demo = np.repeat(a["n_samples"], a["n_keys"])
        if np.any(a["keypoints"] < 0) or np.any(a["keypoints"] >= k_demo):
            problems.append("key points out of range")
        elif n and (
            np.any(a["keypoints"][starts] != 0)
            or np.any(a["key_bins"] < 0)
            or np.any(a["key_states"] < 0)
        ):
            problems.append("key points do not start at sample 0")
        if not np.all(np.isin(a["template_index"], a["demo_index"])):
            problems.append("a template is not one of the demonstrations")
    if problems:
        raise ModelFormatError(
            "inconsistent fit statistics (tampered file?): " + "; ".join(problems)
        )
