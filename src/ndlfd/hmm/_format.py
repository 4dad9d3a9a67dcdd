"""The DiscreteHMM file format: named arrays in an ``.npz``, checked on load.

Arrays (with an optional key prefix, so a learner can embed a model in its own
file): ``states`` (sorted seen state ids), ``transition_indptr`` /
``transition_targets`` / ``transition_counts`` (CSR over the seen states),
``emission_indptr`` / ``emission_symbols`` / ``emission_counts``,
``start_counts``, ``sizes`` (``n_states, n_symbols, n_sequences``) and
``pseudo`` (``p`` or NaN for the default ``1 / n_states``, ``r``). Every
array's dtype, shape, range and consistency is checked before the counts are
returned, so a tampered or foreign file is a :class:`ModelFormatError`, never a
crash later.

There is one version so far (:data:`FORMAT_VERSION` 1, read by
:func:`counts_from_arrays_v1`); a new version gets its own reader beside it.
"""

from __future__ import annotations

import os
from collections.abc import Mapping

import numpy as np

from .._errors import ModelFormatError
from .._fileformat import load_npz, save_npz
from ._counts import Counts, row_sums

__all__ = [
    "ARRAY_KEYS",
    "FORMAT_KIND",
    "FORMAT_VERSION",
    "counts_from_arrays",
    "counts_from_arrays_v1",
    "counts_to_arrays",
    "load_counts",
    "save_counts",
]

FORMAT_KIND = "DiscreteHMM"
FORMAT_VERSION = 1

#: The count arrays, in the order they are written (then ``sizes``, ``pseudo``).
ARRAY_KEYS = (
    "states",
    "transition_indptr",
    "transition_targets",
    "transition_counts",
    "emission_indptr",
    "emission_symbols",
    "emission_counts",
    "start_counts",
)


def counts_to_arrays(
    counts: Counts, default_pseudo_transition: bool, prefix: str = ""
) -> dict[str, np.ndarray]:
    """The counts as named numeric arrays (copies).

    Parameters
    ----------
    counts : Counts
    default_pseudo_transition : bool
        Whether ``p`` is the default ``1 / n_states`` (written as NaN).
    prefix : str, default=""
        Prepended to every key.

    Returns
    -------
    arrays : dict of str to ndarray
        :data:`ARRAY_KEYS`, ``sizes`` of shape (3,) and ``pseudo`` of shape (2,).
    """
    out = {prefix + k: getattr(counts, k).copy() for k in ARRAY_KEYS}
    m = counts.n_states
    big = m > np.iinfo(np.int64).max
    out[prefix + "sizes"] = np.array(
        [-1 if big else m, counts.n_symbols, counts.n_sequences], dtype=np.int64
    )
    if big:  # an n_states past int64 (interned states of many columns)
        out[prefix + "n_states_limbs"] = _to_limbs(m)
    p_param = np.nan if default_pseudo_transition else counts.pseudo_transition
    out[prefix + "pseudo"] = np.array(
        [p_param, counts.pseudo_emission], dtype=np.float64
    )
    return out


#: Bits per limb of an ``n_states`` written as limbs (``n_states_limbs``).
_LIMB_BITS = 31


def _to_limbs(m: int) -> np.ndarray:
    """A positive int as little-endian base ``2**31`` limbs (int64)."""
    limbs = []
    while m:
        limbs.append(m & ((1 << _LIMB_BITS) - 1))
        m >>= _LIMB_BITS
    return np.array(limbs, dtype=np.int64)


def _from_limbs(limbs: np.ndarray) -> int:
    """:func:`_to_limbs` undone; -1 for limbs out of range (refused after)."""
    if limbs.size == 0 or limbs.size > 64 or limbs.min() < 0:
        return -1
    if limbs.max() >= 1 << _LIMB_BITS:
        return -1
    return sum(int(v) << (_LIMB_BITS * k) for k, v in enumerate(limbs.tolist()))


def counts_from_arrays(arrays, prefix: str = "") -> tuple[Counts, float | None]:
    """Counts from :func:`counts_to_arrays` output of the current version.

    Parameters
    ----------
    arrays : mapping of str to ndarray
        May hold other keys; only those starting with ``prefix`` are read.
    prefix : str, default=""

    Returns
    -------
    counts : Counts
    pseudo_transition : float or None
        The parameter as given to the model (``None``: the default ``1 / m``).

    Raises
    ------
    ModelFormatError
        If an array is missing or inconsistent (shape, dtype, range, counts).
    """
    return counts_from_arrays_v1(arrays, prefix)


def save_counts(
    path: str | os.PathLike, counts: Counts, default_pseudo_transition: bool
) -> None:
    """Write counts to an ``.npz`` file of kind ``DiscreteHMM`` (atomically)."""
    save_npz(
        path,
        counts_to_arrays(counts, default_pseudo_transition),
        kind=FORMAT_KIND,
        version=FORMAT_VERSION,
        metadata={
            "n_states": counts.n_states,
            "n_symbols": counts.n_symbols,
            "n_seen_states": int(counts.states.shape[0]),
        },
    )


def load_counts(path: str | os.PathLike) -> tuple[Counts, float | None]:
    """Read what :func:`save_counts` wrote; errors name the file."""
    arrays, _ = load_npz(path, kind=FORMAT_KIND, version=FORMAT_VERSION)
    try:
        return counts_from_arrays(arrays, "")
    except ModelFormatError as exc:
        raise ModelFormatError(f"{path}: {exc}") from None


def counts_from_arrays_v1(arrays, prefix: str) -> tuple[Counts, float | None]:
    """Read and check the arrays of format version 1 (:func:`counts_from_arrays`)."""

    def bad(msg: str):
        return ModelFormatError(f"invalid DiscreteHMM arrays: {msg}")

    if not isinstance(arrays, Mapping) or not isinstance(prefix, str):
        raise bad(
            "expected a mapping of names to arrays and a str prefix; got"
            f" {type(arrays).__name__} and {type(prefix).__name__}"
        )

    def get(key: str, kind: str, ndim: int = 1) -> np.ndarray:
        full = prefix + key
        if full not in arrays:
            raise bad(f"missing array {full!r}")
        try:
            a = np.asarray(arrays[full])
        except (ValueError, TypeError):  # ragged nested lists
            raise bad(f"{full!r} must be an array; got a ragged sequence") from None
        if a.dtype.kind != kind or a.ndim != ndim:
            want = {"i": "integer", "f": "float"}[kind]
            raise bad(
                f"{full!r} must be a {ndim}-D {want} array; got shape {a.shape} and"
                f" dtype {a.dtype}"
            )
        return np.ascontiguousarray(a, dtype=np.int64 if kind == "i" else np.float64)

    sizes = get("sizes", "i")
    pseudo = get("pseudo", "f")
    if sizes.shape != (3,) or pseudo.shape != (2,):
        raise bad(
            f"'sizes' must have shape (3,) and 'pseudo' shape (2,); got"
            f" {sizes.shape} and {pseudo.shape}"
        )
    m, nt, n_seq = (int(v) for v in sizes)
    if m == -1 and prefix + "n_states_limbs" in arrays:
        m = _from_limbs(get("n_states_limbs", "i"))
        if m <= np.iinfo(np.int64).max:
            raise bad("'n_states_limbs' must hold an n_states past int64")
    if m < 1 or nt < 1 or n_seq < 1:
        raise bad(f"sizes (n_states, n_symbols, n_sequences) must be >= 1; got {sizes}")
    p_param, r = float(pseudo[0]), float(pseudo[1])
    if not (np.isnan(p_param) or (np.isfinite(p_param) and p_param >= 0)):
        raise bad(f"pseudo_transition must be NaN (default) or >= 0; got {p_param}")
    if not (np.isfinite(r) and r >= 0):
        raise bad(f"pseudo_emission must be finite and >= 0; got {r}")
    seen = get("states", "i")
    n_seen = seen.shape[0]
    if n_seen < 1 or n_seen > m:
        raise bad(f"'states' must hold 1..{m} seen states; got {n_seen}")
    if seen[0] < 0 or seen[-1] >= m or np.any(np.diff(seen) <= 0):
        raise bad(f"'states' must be strictly increasing ids in 0..{m - 1}")

    def csr(name: str, n_cols: int, what: str):
        indptr = get(f"{name}_indptr", "i")
        cols = get(f"{name}_{what}", "i")
        counts = get(f"{name}_counts", "i")
        if indptr.shape != (n_seen + 1,) or indptr[0] != 0:
            raise bad(f"'{name}_indptr' must have shape ({n_seen + 1},) and start at 0")
        if np.any(np.diff(indptr) < 0) or indptr[-1] != cols.shape[0]:
            raise bad(f"'{name}_indptr' must be non-decreasing and end at {cols.size}")
        if counts.shape != cols.shape or np.any(counts < 1):
            raise bad(f"'{name}_counts' must be >= 1, one per entry")
        if cols.size and (cols.min() < 0 or cols.max() >= n_cols):
            raise bad(f"'{name}_{what}' must lie in 0..{n_cols - 1}")
        row = np.repeat(np.arange(n_seen), np.diff(indptr))
        if cols.size > 1:
            same_row = row[1:] == row[:-1]
            if np.any(same_row & (cols[1:] <= cols[:-1])):
                raise bad(f"'{name}_{what}' must be strictly increasing in each row")
        return indptr, cols, counts

    t_indptr, t_dst, t_cnt = csr("transition", n_seen, "targets")
    e_indptr, e_sym, e_cnt = csr("emission", nt, "symbols")
    f_cnt = get("start_counts", "i")
    if f_cnt.shape != (n_seen,) or np.any(f_cnt < 0) or f_cnt.sum() != n_seq:
        raise bad(
            f"'start_counts' must be {n_seen} counts >= 0 summing to n_sequences ="
            f" {n_seq}"
        )
    # every occurrence of a state is entered by a transition or starts a sequence,
    # and either leaves by a transition or ends one
    e_tot = row_sums(e_indptr, e_cnt)
    n_out = row_sums(t_indptr, t_cnt)
    n_in = np.bincount(t_dst, weights=t_cnt, minlength=n_seen).astype(np.int64)
    if (
        np.any(e_tot < 1)
        or np.any(e_tot != n_in + f_cnt)
        or np.any(e_tot < n_out)
        or int((e_tot - n_out).sum()) != n_seq
    ):
        raise bad(
            "emission counts are inconsistent with the transition and start counts"
        )
    p = 1.0 / m if np.isnan(p_param) else p_param
    counts = Counts(
        m, nt, p, r, n_seq, seen, t_indptr, t_dst, t_cnt, e_indptr, e_sym, e_cnt,
        f_cnt,
    )  # fmt: skip
    return counts, None if np.isnan(p_param) else p_param
