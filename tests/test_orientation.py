import numpy as np
import pytest
from hypothesis import example, given, settings
from hypothesis import strategies as st
from hypothesis.extra import numpy as hnp
from scipy.spatial.transform import Rotation

from ndlfd._errors import OptionError, ValidationError
from ndlfd.orientation import (
    check_quaternions,
    make_continuous,
    normalize_quaternions,
    to_order,
)


def _reference_continuous(Q):
    """Loop version: compare each row with the previous *output* row.

    Follows make_continuous's stated tie rule with Python floats: the dot
    product summed left to right, a tie within 4 eps sum|q_k p_k| of zero.
    """
    eps = np.finfo(np.float64).eps
    out = [[float(v) for v in Q[0]]]
    for row in Q[1:]:
        q = [float(v) for v in row]
        p = out[-1]
        dot = 0.0
        magnitude = 0.0
        for k in range(4):
            dot = q[k] * p[k] if k == 0 else dot + q[k] * p[k]
            magnitude = abs(q[k] * p[k]) if k == 0 else magnitude + abs(q[k] * p[k])
        out.append([-v for v in q] if dot < -4.0 * eps * magnitude else q)
    return np.array(out, dtype=float)


def _smooth_stream(n, seed):
    rng = np.random.default_rng(seed)
    steps = Rotation.from_rotvec(rng.normal(scale=0.2, size=(n, 3)))
    r = Rotation.identity()
    rots = []
    for k in range(n):
        r = steps[k] * r
        rots.append(r)
    return Rotation.concatenate(rots)


def test_make_continuous_on_stream_with_sign_flips():
    rots = _smooth_stream(200, 0)
    q_xyzw = rots.as_quat()
    rng = np.random.default_rng(1)
    flips = rng.random(200) < 0.4
    noisy = np.where(flips[:, None], -q_xyzw, q_xyzw)
    Q = check_quaternions(noisy, order="xyzw")
    C = make_continuous(Q)
    # consecutive dots are non-negative
    assert np.all(np.einsum("ij,ij->i", C[1:], C[:-1]) >= 0)
    # the rotations are unchanged (independent check through scipy)
    back = Rotation.from_quat(to_order(C, "xyzw"))
    np.testing.assert_allclose(back.as_matrix(), rots.as_matrix(), atol=1e-12)
    # and equal to the obvious loop
    np.testing.assert_array_equal(C, _reference_continuous(Q))
    # every row is +-its input row
    assert np.all(np.isin(np.round(C / Q, 12), [-1.0, 1.0]) | (Q == 0))


# Found by hypothesis: the dot product is -0.5 + 0.25 + 0.25 - 9e-176, zero up
# to rounding; summed in another order it is exactly 0.0.
_ROUNDING_TIE = [[0.5, 0.5, 0.5, 0.5], [-1.0, 0.5, 0.5, -1.8e-175]]


@settings(max_examples=80, deadline=None)
@given(
    hnp.arrays(
        np.float64,
        st.tuples(st.integers(1, 30), st.just(4)),
        elements=st.sampled_from([-1.0, 0.0, 0.5, 1.0]) | st.floats(-1, 1),
    )
)
@example(np.array(_ROUNDING_TIE))
@example(np.array(_ROUNDING_TIE[::-1]))
def test_make_continuous_matches_reference(Q):
    np.testing.assert_array_equal(make_continuous(Q), _reference_continuous(Q))


@pytest.mark.parametrize("Q", [_ROUNDING_TIE, _ROUNDING_TIE[::-1]])
@pytest.mark.parametrize("scale", [1.0, -1.0, 3.0])
def test_make_continuous_keeps_a_rounding_tie(Q, scale):
    # Left to right the dot product is -9e-176 (negative), pairwise it is 0.0:
    # both are ties, so the second row is kept as given, whatever its sign.
    Q = np.array(Q) * [[1.0], [scale]]
    assert np.dot(Q[0], Q[1]) != np.einsum("ij,ij->i", Q[1:], Q[:-1])[0]
    np.testing.assert_array_equal(make_continuous(Q), Q)
    np.testing.assert_array_equal(_reference_continuous(Q), Q)
    # moved a little towards -Q[0], the dot product is below -tol: not a tie
    Q[1] -= 1e-12 * Q[0]
    np.testing.assert_array_equal(make_continuous(Q), Q * [[1.0], [-1.0]])


def test_scalar_last_round_trip_with_scipy():
    rots = Rotation.from_rotvec(np.random.default_rng(2).normal(size=(20, 3)))
    xyzw = rots.as_quat()
    wxyz = check_quaternions(xyzw, order="xyzw")
    np.testing.assert_array_equal(wxyz[:, 0], xyzw[:, 3])
    np.testing.assert_array_equal(wxyz[:, 1:], xyzw[:, :3])
    np.testing.assert_array_equal(to_order(wxyz, "xyzw"), xyzw)
    np.testing.assert_array_equal(to_order(wxyz, "wxyz"), wxyz)
    np.testing.assert_array_equal(check_quaternions(wxyz), wxyz)
    back = Rotation.from_quat(to_order(wxyz, "xyzw"))
    np.testing.assert_allclose(back.as_matrix(), rots.as_matrix(), atol=1e-12)


def test_check_quaternions_refuses_non_unit_naming_the_row():
    Q = np.tile([1.0, 0, 0, 0], (5, 1))
    Q[3] = [0.9, 0, 0, 0]
    with pytest.raises(
        ValidationError,
        match=r"unit norm \(rows within 0.001 of it are renormalized\); got norm"
        r" 0.9 at row 3",
    ):
        check_quaternions(Q)
    Q[3] = [1 + 1e-7, 0, 0, 0]  # within tolerance: kept as it is
    np.testing.assert_array_equal(check_quaternions(Q), Q)
    with pytest.raises(ValidationError, match="at row 3"):
        check_quaternions(Q, atol=1e-9, renormalize_tol=0.0)


def test_quaternions_logged_to_four_decimals_are_renormalized_with_one_warning():
    from scipy.spatial.transform import Rotation

    from ndlfd import NdlfdWarning

    q = Rotation.from_euler("xyz", np.random.default_rng(0).normal(size=(50, 3)))
    logged = np.round(q.as_quat(scalar_first=True), 4)  # norms off by up to ~2e-4
    off = np.abs(np.linalg.norm(logged, axis=1) - 1) > 1e-6
    assert off.any()
    with pytest.warns(NdlfdWarning, match=rf"renormalized {off.sum()} of 50") as rec:
        out = check_quaternions(logged)
    assert len(rec) == 1
    norms = np.linalg.norm(out, axis=1)
    np.testing.assert_allclose(norms[off], 1.0, rtol=0, atol=1e-15)
    np.testing.assert_array_equal(out[~off], logged[~off])  # within 1e-6: kept
    bad = logged.copy()
    bad[7] *= 1.002  # beyond the repair tolerance: still an error
    with pytest.raises(ValidationError, match="at row 7"):
        check_quaternions(bad)


@pytest.mark.parametrize(
    ("Q", "match"),
    [
        ([[1.0, 0, 0]], r"shape \(n_samples, 4\).*got an array of shape \(1, 3\)"),
        ([1.0, 0, 0, 0], r"must have shape \(n_points, n_dims\)"),
        ([[np.nan, 0, 0, 0]], r"finite.*at row 0"),
        ([["a", "b", "c", "d"]], "real numbers"),
    ],
)
def test_check_quaternions_shape_errors(Q, match):
    with pytest.raises(ValidationError, match=match):
        check_quaternions(Q)


def test_unknown_order():
    with pytest.raises(OptionError, match=r"unknown quaternion_order 'zyxw'.*'wxyz'"):
        check_quaternions([[1.0, 0, 0, 0]], order="zyxw")
    with pytest.raises(OptionError, match="expected one of: 'wxyz', 'xyzw'"):
        to_order([[1.0, 0, 0, 0]], "WXYZ")


@settings(max_examples=50, deadline=None)
@given(
    hnp.arrays(
        np.float64,
        st.tuples(st.integers(1, 20), st.just(4)),
        elements=st.floats(-100, 100, allow_nan=False),
    ).filter(lambda a: np.all(np.linalg.norm(a, axis=1) > 1e-6))
)
def test_normalize_quaternions_property(Q):
    U = normalize_quaternions(Q)
    np.testing.assert_allclose(np.linalg.norm(U, axis=1), 1.0, rtol=1e-12)
    # parallel, same direction: U * |Q| == Q
    np.testing.assert_allclose(U * np.linalg.norm(Q, axis=1)[:, None], Q, atol=1e-9)
    check_quaternions(U, atol=1e-12)


def test_normalize_quaternions_zero_rows():
    Q = [[2.0, 0, 0, 0], [0.0, 0, 0, 0]]
    with pytest.raises(ValidationError, match=r"non-zero norm .* at row 1"):
        normalize_quaternions(Q)
    np.testing.assert_array_equal(
        normalize_quaternions(Q, zero="identity"), [[1, 0, 0, 0], [1, 0, 0, 0]]
    )
    with pytest.raises(ValidationError, match="zero must be 'error' or 'identity'"):
        normalize_quaternions(Q, zero="skip")
