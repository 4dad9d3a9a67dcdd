"""Exact sums: values split into integer limbs that add up in any order.

The centroid sums of a fit (:class:`~ndlfd.learner.FitStats`) are held as
limbs, so merging the statistics of parts of the demonstrations gives the same
sums bit for bit, whatever the parts and their order.
"""

from __future__ import annotations

import numpy as np

from .._errors import ValidationError
from ._fit_kernels import split_limbs

__all__ = [
    "LIMB_BITS",
    "MIN_EXPONENT",
    "N_LIMBS",
    "from_limbs",
    "scale_exponents",
    "to_limbs",
]

#: Bits per integer limb of a centroid sum (three limbs: 93 bits below the
#: column's bound). A limb is at most 2**31 in size, so up to 2**31 key points
#: of one state add up in int64 without overflow.
LIMB_BITS = 31
N_LIMBS = 3
#: Smallest scale exponent (keeps the finest limb's quantum a normal float).
MIN_EXPONENT = -900


def scale_exponents(bound) -> np.ndarray:
    """Per column the exponent ``E`` with ``|u| <= 2**E`` for every value ``u``.

    Parameters
    ----------
    bound : array-like of shape (n_dims,)
        The largest absolute value of each column (finite, >= 0).

    Returns
    -------
    exponents : ndarray of shape (n_dims,), dtype int64

    Examples
    --------
    >>> scale_exponents([1.0, 0.75, 3.0, 0.0])
    array([   1,    0,    2, -900])
    """
    b = np.asarray(bound, dtype=np.float64)
    e = np.frexp(b)[1].astype(np.int64)  # b = m * 2**e with 0.5 <= m < 1
    e[b == 0] = MIN_EXPONENT
    return np.maximum(e, MIN_EXPONENT)


def _quanta(exponents: np.ndarray) -> list[np.ndarray]:
    e = np.asarray(exponents, dtype=np.int64)
    return [np.ldexp(1.0, e - LIMB_BITS * (k + 1)) for k in range(N_LIMBS)]


def to_limbs(values, exponents) -> np.ndarray:
    """Split values exactly into integer multiples of fixed powers of two.

    With ``q_k = 2**(E - 31 k)`` (``E`` the column's exponent from
    :func:`scale_exponents`), ``u = a_1 q_1 + a_2 q_2 + a_3 q_3 + r`` with
    integers ``|a_k| <= 2**31`` (truncated towards zero, so every step is
    exact in floating point) and a remainder ``|r| < 2**(E - 93)`` that is
    dropped. Integer limbs add up exactly and in any order, so a sum of
    values held as limbs does not depend on how it was split.

    Parameters
    ----------
    values : array-like of shape (n, n_dims)
        Values with ``|u| <= 2**E`` per column.
    exponents : array-like of shape (n_dims,)

    Returns
    -------
    limbs : ndarray of shape (3, n, n_dims), dtype int64

    Examples
    --------
    >>> L = to_limbs([[0.5], [0.25]], [0])
    >>> L[:, :, 0]
    array([[1073741824,  536870912],
           [         0,          0],
           [         0,          0]])
    >>> from_limbs(L.sum(axis=1), [0])
    array([0.75])
    """
    r = np.asarray(values, dtype=np.float64)
    q = np.array(_quanta(exponents)).reshape(N_LIMBS, -1)
    if r.ndim != 2 or r.shape[1] != q.shape[1]:
        raise ValidationError(
            f"values must have shape (n, {q.shape[1]}), one column per exponent;"
            f" got shape {r.shape}"
        )
    return split_limbs(r, q)  # compiled: trunc(r / q), r - a q, limb by limb


def from_limbs(limbs, exponents) -> np.ndarray:
    """The float value of summed limbs (``sum_k a_k q_k``, in a fixed order).

    Parameters
    ----------
    limbs : array-like of shape (3, ..., n_dims), integer
    exponents : array-like of shape (n_dims,)

    Returns
    -------
    values : ndarray of shape (..., n_dims)
    """
    L = np.asarray(limbs)
    q = _quanta(exponents)
    out = L[0].astype(np.float64) * q[0]
    for k in range(1, N_LIMBS):
        out = out + L[k].astype(np.float64) * q[k]
    return out
