"""What every fuzz case checks: a correct result or one error of ndlfd's own."""

import warnings

import numpy as np
from hypothesis import strategies as st

from ndlfd import NdlfdError, NdlfdWarning
from ndlfd.demonstration import Demonstration

#: the values that break naive code
NASTY = [np.nan, np.inf, -np.inf, 1e300, -1e300, 1e-300, 0.0, -0.0, 5e-324]


def finite_or_nasty(nasty_rate=0.3):
    """Floats that are ordinary most of the time and one of :data:`NASTY` else."""
    plain = st.floats(-10.0, 10.0, allow_nan=False, allow_infinity=False)
    return st.one_of(plain, st.sampled_from(NASTY)) if nasty_rate else plain


@st.composite
def arrays_2d(draw, max_rows=12, max_cols=4, nasty=True, min_rows=0, min_cols=0):
    """``(n, d)`` float arrays with n, d from 0, NaN/inf/1e300 or constant rows."""
    n = draw(st.integers(min_rows, max_rows))
    d = draw(st.integers(min_cols, max_cols))
    kind = draw(st.sampled_from(["values", "constant", "tiny-range", "huge"]))
    elems = finite_or_nasty() if nasty else finite_or_nasty(0)
    X = np.array(draw(st.lists(elems, min_size=n * d, max_size=n * d)), float)
    X = X.reshape(n, d)
    if kind == "constant" and n:
        X[:] = X[:1]
    elif kind == "tiny-range":
        X = 1.0 + 1e-300 * np.abs(X)
    elif kind == "huge":
        with np.errstate(over="ignore"):
            X = X * 1e300
    return X


BAD_OBJECTS = [
    "abc",
    [["a", "b"], ["c", "d"]],
    [[1.0, 2.0], [3.0]],
    np.array([[1 + 2j, 3]]),
    np.array([[True, False], [False, True]]),
    np.array([[1.0, None]], dtype=object),
    None,
    {"x": 1},
    np.zeros((2, 2, 2)),
    np.zeros(()),
]


def check_outcome(fn, *args, **kwargs):
    """Call ``fn``; return its result, or ``None`` after one :class:`NdlfdError`.

    Anything else (a bare numpy error, a TypeError, RecursionError, a numba
    typing error) fails the test; so does NaN or inf in an array result.
    """
    try:
        with warnings.catch_warnings():
            warnings.simplefilter("ignore", NdlfdWarning)  # a repair, said once
            out = fn(*args, **kwargs)
    except NdlfdError as exc:
        assert str(exc).strip(), "an error without a message"
        return None
    assert_finite(out)
    return out


def assert_finite(out):
    """No NaN or inf anywhere in ``out`` (arrays, tuples, lists, demonstrations)."""
    if isinstance(out, Demonstration):
        assert np.isfinite(out.X).all() and np.isfinite(out.t).all(), out
    elif isinstance(out, np.ndarray) and out.dtype.kind in "fc":
        assert np.isfinite(out).all(), out
    elif isinstance(out, (tuple, list)):
        for o in out:
            assert_finite(o)
