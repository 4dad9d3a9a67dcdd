"""Fuzz the array doorways: simplify, GroupScaler, Codebook, TimeBins, Demonstration.

Every input gets a correct result or one :class:`ndlfd.NdlfdError`; never a bare
numpy error, a numba typing error, a RecursionError or NaN in an output.
"""

import numpy as np
import pytest
from fuzz_helpers import BAD_OBJECTS, arrays_2d, check_outcome, finite_or_nasty
from hypothesis import HealthCheck, given, settings
from hypothesis import strategies as st

import ndlfd
from ndlfd import Codebook, Demonstration, GroupScaler, TimeBins
from ndlfd.demonstration import unit_time

FUZZ = settings(
    max_examples=60, deadline=None, suppress_health_check=[HealthCheck.too_slow]
)


@FUZZ
@given(
    P=arrays_2d(),
    eps=st.one_of(finite_or_nasty(), st.sampled_from([-1.0, 0.0, 1e-300])),
    distance=st.sampled_from(["line", "segment", "sed", "paper", "nope"]),
    n_points=st.one_of(st.none(), st.integers(-2, 20)),
)
def test_fuzz_simplify(P, eps, distance, n_points):
    n = P.shape[0]
    times = np.arange(n, dtype=float) if distance == "sed" else None
    if n_points is not None:
        out = check_outcome(
            ndlfd.simplify, P, distance=distance, n_points=n_points, times=times
        )
    else:
        out = check_outcome(ndlfd.simplify, P, eps, distance=distance, times=times)
    if out is not None:
        assert out.dtype == np.int64
        assert out[0] == 0 and out[-1] == n - 1
        assert (np.diff(out) > 0).all()


@pytest.mark.parametrize("bad", BAD_OBJECTS, ids=repr)
def test_fuzz_simplify_wrong_types(bad):
    assert check_outcome(ndlfd.simplify, bad, 0.1) is None
    assert check_outcome(ndlfd.simplify_many, [bad], 0.1) is None
    assert check_outcome(ndlfd.simplify, [[0.0], [1.0]], bad) is None


@FUZZ
@given(Ps=st.lists(arrays_2d(max_cols=2), max_size=4), eps=finite_or_nasty())
def test_fuzz_simplify_many(Ps, eps):
    out = check_outcome(ndlfd.simplify_many, Ps, eps)
    if out is not None:
        assert len(out) == len(Ps)


def test_fuzz_simplify_long_zigzag():
    """A long zigzag keeps every corner, without recursion.

    1e5 points here: at 1e6 points with every corner kept the kernel splits one
    point off per step (quadratic, over 100 s; see docs/robustness.md).
    """
    n = 100_000
    P = np.column_stack([np.arange(n, dtype=float), (np.arange(n) % 2) * 1.0])
    idx = ndlfd.simplify(P, 0.5)
    np.testing.assert_array_equal(idx, np.arange(n))
    assert ndlfd.simplify(P, 2.0).tolist() == [0, n - 1]


@FUZZ
@given(
    t=st.lists(finite_or_nasty(), max_size=8),
    X=arrays_2d(max_rows=8, max_cols=3),
    order=st.sampled_from(["as-is", "sorted", "decreasing", "duplicated"]),
)
def test_fuzz_demonstration(t, X, order):
    t = np.array(t, float)
    if order == "sorted":
        t = np.sort(t)
    elif order == "decreasing":
        t = -np.sort(t)
    elif order == "duplicated" and t.size:
        t = np.sort(np.concatenate([t, t[:1]]))
    d = X.shape[1]
    demo = check_outcome(
        Demonstration,
        t,
        X,
        tuple(f"c{j}" for j in range(d)),
        ("position",) * d,
    )
    if demo is not None:
        assert (np.diff(demo.t) > 0).all()
        assert len(demo.t) == len(demo.X)
        u = check_outcome(unit_time, demo.t)
        if u is not None:
            assert u[0] == 0.0 and u[-1] <= 1.0


@pytest.mark.parametrize("bad", BAD_OBJECTS, ids=repr)
def test_fuzz_demonstration_wrong_types(bad):
    assert check_outcome(Demonstration.from_arrays, bad, position=[[0, 0]]) is None
    assert check_outcome(Demonstration.from_arrays, [0.0, 1.0], position=bad) is None


def _demo(X, t=None):
    t = np.arange(len(X), dtype=float) if t is None else t
    return Demonstration.from_arrays(t, position=X)


@FUZZ
@given(
    Xs=st.lists(arrays_2d(max_rows=6, max_cols=2, nasty=False), min_size=1, max_size=3),
    scale=st.sampled_from([1.0, 1e300, 1e-300, 0.0]),
    mode=st.sampled_from(["group", "per-dimension", "none", "bogus"]),
    probe=arrays_2d(max_rows=4, max_cols=2),
)
def test_fuzz_group_scaler(Xs, scale, mode, probe):
    with np.errstate(over="ignore"):
        demos = [check_outcome(_demo, X * scale) for X in Xs]
    if any(d is None for d in demos):
        return
    scaler = check_outcome(GroupScaler(mode=mode).fit, demos)
    if scaler is None:
        return
    U = check_outcome(scaler.transform, probe)
    if U is not None:
        back = check_outcome(scaler.inverse_transform, U)
        assert back is None or back.shape == probe.shape


@FUZZ
@given(
    levels=st.lists(
        st.one_of(st.integers(-2, 5), st.sampled_from([2**40, 2**62, 2**63])),
        max_size=4,
    ),
    U=arrays_2d(max_rows=5, max_cols=4),
)
def test_fuzz_codebook(levels, U):
    cb = check_outcome(Codebook, levels)
    if cb is None:
        return
    s = check_outcome(cb.encode, U)
    if s is not None:
        assert s.dtype == np.int64 and (s >= 0).all()
        back = check_outcome(cb.decode, s)
        assert back is not None and ((back >= 0) & (back <= 1)).all()


def test_fuzz_codebook_overflowing_int64_numbers_are_refused_cells_are_not():
    for levels in ([2**32, 2**32], [100] * 10):
        cb = Codebook(levels)
        assert cb.cells([[0.5] * len(levels)]).shape == (1, len(levels))
        with pytest.raises(ndlfd.ValidationError, match="int64"):
            cb.encode([[0.5] * len(levels)])
    with pytest.raises(ndlfd.ValidationError, match="at most"):
        Codebook([2**63])  # one level index past int64


@pytest.mark.parametrize("bad", [*BAD_OBJECTS, 1.5, True, -1, 0], ids=repr)
def test_fuzz_codebook_and_time_bins_wrong_types(bad):
    assert check_outcome(Codebook, bad) is None
    assert check_outcome(TimeBins, bad) is None
    assert check_outcome(Codebook([3, 3]).decode, bad) is None
    assert check_outcome(Codebook([3, 3]).encode, bad) is None


@FUZZ
@given(
    n_bins=st.integers(1, 50),
    t=st.lists(finite_or_nasty(), max_size=8),
    order=st.sampled_from(["as-is", "sorted"]),
)
def test_fuzz_time_bins(n_bins, t, order):
    t = np.array(t, float)
    if order == "sorted":
        t = np.sort(t)
    k = check_outcome(TimeBins(n_bins).transform, t)
    if k is not None:
        assert ((k >= 0) & (k < n_bins)).all()
