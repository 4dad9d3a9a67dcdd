import tracemalloc

import numpy as np
import pytest
from hypothesis import given
from hypothesis import strategies as st

import ndlfd
from ndlfd import NdlfdError, OptionError, ResourceLimitError, ValidationError
from ndlfd._registry import Registry
from ndlfd._validation import (
    MAX_TIME_BINS,
    MAX_VALUES,
    MAX_WORK_BYTES,
    as_float_array,
    check_int_sequence,
    check_n_time_bins,
    check_nonnegative_scalar,
    check_points,
    check_positive_int,
    check_random_state,
    check_times,
    check_weights,
    check_work_size,
)


def test_error_hierarchy_is_valueerror():
    assert issubclass(NdlfdError, ValueError)
    assert issubclass(ValidationError, NdlfdError)
    assert issubclass(OptionError, NdlfdError)


def test_check_points_converts_ints_to_contiguous_float():
    P = check_points(np.arange(6).reshape(3, 2)[:, ::-1])
    assert P.dtype == np.float64 and P.flags.c_contiguous
    np.testing.assert_array_equal(P, [[1, 0], [3, 2], [5, 4]])


@pytest.mark.parametrize(
    ("bad", "match"),
    [
        ([1.0, 2.0], r"shape \(n_points, n_dims\); got an array of shape \(2,\)"),
        (np.zeros((2, 2, 2)), r"got an array of shape \(2, 2, 2\)"),
        (np.zeros((0, 2)), r"at least 1 row"),
        (np.zeros((3, 0)), r"at least one column"),
        ([["a", "b"]], r"real numbers .* got .* dtype <U1"),
        ([[1, 2], [3]], r"rectangular"),
        ([[True, False]], r"real numbers"),
        (np.array([[1 + 1j, 0]]), r"real numbers"),
    ],
)
def test_check_points_rejects(bad, match):
    with pytest.raises(ValidationError, match=match):
        check_points(bad)


def test_check_points_names_first_nonfinite_row():
    P = np.zeros((5, 3))
    P[3, 1] = np.nan
    P[4, 0] = np.inf
    with pytest.raises(ValidationError, match="at row 3"):
        check_points(P)


def test_check_points_hint_for_1d():
    with pytest.raises(ValidationError, match=r"np.column_stack\(\[t, y\]\)"):
        check_points(np.arange(4.0))


@given(st.lists(st.floats(-1e6, 1e6), min_size=2, max_size=30, unique=True))
def test_check_times_accepts_sorted_unique(values):
    values = sorted(values)
    t = check_times(values)
    assert t.dtype == np.float64 and t.shape == (len(values),)
    assert t.tolist() == values  # unchanged
    assert check_times(tuple(values), n=len(values)).tolist() == values


@pytest.mark.parametrize(
    ("bad", "match"),
    [
        ([0.0, 1.0, 1.0], r"strictly increasing; got times\[2\] = 1 after"),
        ([0.0, np.nan], r"finite"),
        ([[0.0, 1.0]], r"shape \(n_samples,\)"),
    ],
)
def test_check_times_rejects(bad, match):
    with pytest.raises(ValidationError, match=match):
        check_times(bad)


def test_check_times_length():
    with pytest.raises(ValidationError, match=r"length 3\); got length 2"):
        check_times([0, 1], n=3)


def test_check_nonnegative_scalar_accepts():
    for value, want in ((0, 0.0), (2, 2.0), (0.25, 0.25), (np.float32(0.5), 0.5)):
        got = check_nonnegative_scalar(value, "epsilon")
        assert type(got) is float and got == want
    assert check_nonnegative_scalar(np.int64(3), "epsilon") == 3.0


@pytest.mark.parametrize("bad", [-1, np.nan, np.inf, "1", None, True])
def test_check_nonnegative_scalar_rejects(bad):
    with pytest.raises(ValidationError, match="finite number >= 0"):
        check_nonnegative_scalar(bad, "epsilon")


def test_check_positive_int():
    got = check_positive_int(np.int64(4), "k")
    assert type(got) is int and got == 4
    assert check_positive_int(2, "k", minimum=2) == 2
    with pytest.raises(ValidationError, match="integer >= 2; got 1"):
        check_positive_int(1, "k", minimum=2)
    for bad in (0, -3, 1.0, "2", True):
        with pytest.raises(ValidationError, match="integer >= 1"):
            check_positive_int(bad, "k")


def test_check_weights():
    np.testing.assert_array_equal(check_weights([1, 0], 2), [1.0, 0.0])
    with pytest.raises(ValidationError, match=r"weights\[1\] = -1"):
        check_weights([1, -1], 2)
    with pytest.raises(ValidationError, match=r"weights\[0\] = nan"):
        check_weights([np.nan, 1], 2)


def test_check_int_sequence():
    np.testing.assert_array_equal(
        check_int_sequence(np.array([1.0, 2.0]), "s", low=0, high=3), [1, 2]
    )
    with pytest.raises(ValidationError, match="whole numbers"):
        check_int_sequence([0.5], "s", low=0, high=3)
    with pytest.raises(ValidationError, match="1-D"):
        check_int_sequence([[0]], "s", low=0, high=3)
    with pytest.raises(ValidationError, match=r"lie in 0..2; got s\[0\] = -1"):
        check_int_sequence([-1], "s", low=0, high=3)


def test_check_random_state():
    g = np.random.default_rng(1)
    assert check_random_state(g) is g
    # an int seeds a fresh default_rng: the same stream as numpy's own
    a = check_random_state(5).random(3)
    np.testing.assert_array_equal(a, np.random.default_rng(5).random(3))
    np.testing.assert_array_equal(check_random_state(np.int64(5)).random(3), a)
    # a legacy RandomState seeds a Generator from one draw: reproducible
    b = check_random_state(np.random.RandomState(0)).random(3)
    seed = np.random.RandomState(0).randint(0, 2**31 - 1)
    np.testing.assert_array_equal(b, np.random.default_rng(seed).random(3))
    # None: fresh entropy, so two generators differ
    assert isinstance(check_random_state(None), np.random.Generator)
    assert check_random_state(None).random() != check_random_state(None).random()
    with pytest.raises(ValidationError, match="random_state"):
        check_random_state("seed")


def test_registry_lists_choices():
    r = Registry("distance")
    r.add("line", 1)
    r.add("sed", 2)
    assert r.names == ("line", "sed")
    assert "line" in r and list(r) == ["line", "sed"]
    with pytest.raises(OptionError, match=r"unknown distance 'lin'; .*'line', 'sed'"):
        r.get("lin")
    with pytest.raises(OptionError):
        r.get(3)
    with pytest.raises(KeyError):
        r.add("line", 3)


# ------------------------------------------------------------------ resource bounds


def _peak_bytes(fn, *args, **kwargs):
    """Peak traced allocation of a call that raises ResourceLimitError."""
    tracemalloc.start()
    try:
        with pytest.raises(ResourceLimitError) as info:
            fn(*args, **kwargs)
        return tracemalloc.get_traced_memory()[1], str(info.value)
    finally:
        tracemalloc.stop()


def test_resource_limit_error_is_a_validation_error():
    assert issubclass(ResourceLimitError, ValidationError)
    assert ndlfd.ResourceLimitError is ResourceLimitError


def test_bounds_follow_from_the_work_array_bound():
    assert MAX_WORK_BYTES == 2 * 2**30
    assert MAX_VALUES * 8 == MAX_WORK_BYTES
    assert (MAX_TIME_BINS + 1) * 8 == MAX_WORK_BYTES


def test_check_work_size_at_and_above_the_bound():
    check_work_size(MAX_WORK_BYTES, "exactly the bound")  # accepted
    with pytest.raises(ResourceLimitError, match=r"x would need 2,048 MiB, above"):
        check_work_size(MAX_WORK_BYTES + 1, "x")
    with pytest.raises(ResourceLimitError, match=r"bound of 2,048 MiB.* Do less\.$"):
        check_work_size(10**30, "huge", "Do less.")  # Python ints: no overflow


@pytest.mark.parametrize(
    "check",
    [
        lambda a: as_float_array(a, "X"),
        lambda a: check_points(a, "points"),
        lambda a: check_int_sequence(a[:, 0], "states", low=0, high=2),
    ],
)
def test_arrays_above_max_values_are_refused_before_the_copy(check):
    # a zero-stride view: the input itself costs nothing, its copy would be 2 GiB
    big = np.broadcast_to(np.int64(0), (MAX_VALUES + 1, 1))
    peak, msg = _peak_bytes(check, big)
    assert peak < 2**20
    assert f"at most {MAX_VALUES:,} values" in msg and f"got {MAX_VALUES + 1:,}" in msg
    ok = np.broadcast_to(np.int64(0), (1000, 1))  # far below: converted
    assert np.asarray(check(ok)).size == 1000


def test_check_n_time_bins_bound():
    assert check_n_time_bins(MAX_TIME_BINS, "n_bins") == MAX_TIME_BINS
    with pytest.raises(ResourceLimitError, match=r"n_bins must be at most 268,435,455"):
        check_n_time_bins(MAX_TIME_BINS + 1, "n_bins")
    with pytest.raises(ValidationError, match=r">= 1; got 0"):
        check_n_time_bins(0, "n_bins")
    with pytest.raises(ResourceLimitError, match=r"n_points must be at most 5 \(w\)"):
        check_positive_int(6, "n_points", maximum=5, why="w")
