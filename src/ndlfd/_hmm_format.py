"""The DiscreteHMM file format: named arrays in an ``.npz``, checked on load.

Arrays (with an optional key prefix, so a learner can embed a model in its own
file): ``states`` (sorted seen state ids), ``transition_indptr`` /
``transition_targets`` / ``transition_counts`` (CSR over the seen states),
``emission_indptr`` / ``emission_symbols`` / ``emission_counts``,
``start_counts`` and ``params`` (``n_states, n_symbols, p, r, n_sequences``).
Every array's dtype, shape, range and consistency is checked before a model is
built, so a tampered or foreign file is a :class:`ModelFormatError`, never a
crash later.
"""

from __future__ import annotations

import numpy as np

from ._errors import ModelFormatError

__all__ = ["FORMAT_KIND", "FORMAT_VERSION", "model_from_arrays"]

FORMAT_KIND = "DiscreteHMM"
FORMAT_VERSION = 1


def model_from_arrays(cls, arrays, prefix: str):
    """Build a ``cls`` (a DiscreteHMM class) from checked arrays."""
    from ._hmm_model import _row_sums

    def bad(msg: str):
        return ModelFormatError(f"invalid DiscreteHMM arrays: {msg}")

    def get(key: str, kind: str, ndim: int = 1) -> np.ndarray:
        full = prefix + key
        if full not in arrays:
            raise bad(f"missing array {full!r}")
        a = np.asarray(arrays[full])
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
    e_tot = _row_sums(e_indptr, e_cnt)
    n_out = _row_sums(t_indptr, t_cnt)
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
    model = cls(
        m,
        nt,
        pseudo_transition=None if np.isnan(p_param) else p_param,
        pseudo_emission=r,
    )
    p = 1.0 / m if np.isnan(p_param) else p_param
    model._set_fitted(
        m, nt, p, r, seen, t_indptr, t_dst, t_cnt, e_indptr, e_sym, e_cnt, f_cnt,
        n_seq,
    )  # fmt: skip
    return model
