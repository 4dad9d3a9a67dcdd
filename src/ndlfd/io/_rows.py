"""Rows with NaN or inf: an error naming them, or dropped (``bad_rows``)."""

from __future__ import annotations

import numpy as np

from .._errors import DataFileError, ValidationError
from .._repairs import repaired

__all__ = ["BAD_ROWS", "check_bad_rows", "drop_bad_rows"]

#: What ``bad_rows`` may be: ``"error"`` (a row with NaN or inf is an error
#: naming it) or ``"drop"`` (such rows are dropped, with a summary warning).
BAD_ROWS = ("error", "drop")


def check_bad_rows(bad_rows) -> str:
    """``bad_rows`` if it is ``"error"`` or ``"drop"``, else a clear error."""
    if bad_rows not in BAD_ROWS:
        raise ValidationError(
            f"bad_rows must be one of {', '.join(map(repr, BAD_ROWS))}; got"
            f" {bad_rows!r}"
        )
    return bad_rows


def drop_bad_rows(p, t, blocks, lines):
    """Rows with NaN or inf dropped from ``t``, ``blocks`` and ``lines``."""
    ok = np.all([np.isfinite(b).all(axis=1) for b in blocks], axis=0)
    if t is not None:
        ok &= np.isfinite(t)
    n_bad = int(ok.size - ok.sum())
    if n_bad == 0:
        return t, blocks, lines
    if ok.sum() < 2:
        raise DataFileError(
            f"{p}: expected at least 2 rows without NaN or inf; got"
            f" {int(ok.sum())} after dropping {n_bad} of {ok.size}"
        )
    repaired(
        "rows",
        n_bad,
        f"{p}: dropped {n_bad} of {ok.size} row(s) with NaN or inf",
        stacklevel=3,
    )
    t = None if t is None else t[ok]
    lines = None if lines is None else lines[ok]
    return t, [b[ok] for b in blocks], lines
