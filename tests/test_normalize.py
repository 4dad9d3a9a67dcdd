import numpy as np
import pytest
from hypothesis import given, settings
from hypothesis import strategies as st
from hypothesis.extra import numpy as hnp

from ndlfd._errors import NotFittedError, OptionError, ValidationError
from ndlfd.demonstration import Demonstration
from ndlfd.normalize import GroupScaler


def _reference_group_normalize(arrays, groups, weights=None):
    """Element by element: the group's global min/max over all arrays."""
    d = len(groups)
    weights = weights or {}
    out = []
    for a in arrays:
        u = np.empty_like(a, dtype=float)
        for j in range(d):
            cols = [k for k in range(d) if groups[k] == groups[j]]
            lo = min(float(b[:, k].min()) for b in arrays for k in cols)
            hi = max(float(b[:, k].max()) for b in arrays for k in cols)
            for i in range(a.shape[0]):
                u[i, j] = (a[i, j] - lo) / (hi - lo) if hi > lo else a[i, j] - lo
                u[i, j] *= weights.get(groups[j], 1.0)
        out.append(u)
    return out


def _spiral_demo(n=200, scale=1.0):
    s = np.linspace(0.0, 1.0, n)
    P = np.column_stack(
        [-10 + 20 * s, 5 + 5 * np.cos(6 * np.pi * s), 5 * np.sin(6 * np.pi * s)]
    )
    return Demonstration.from_arrays(
        s * 10, position=P * scale, velocity=np.gradient(P, s * 10, axis=0)
    )


def test_group_mode_keeps_proportions_per_dimension_does_not():
    demo = _spiral_demo()  # x spans 20, y and z span 10
    U = GroupScaler().fit_transform(demo)
    P = U[:, :3]
    spans = P.max(axis=0) - P.min(axis=0)
    # one range for the group (x's 20): the spans keep the data's proportions
    raw = demo.get("position")
    raw_spans = raw.max(axis=0) - raw.min(axis=0)
    assert spans[0] == 1.0
    np.testing.assert_allclose(spans, raw_spans / 20.0, rtol=4 * np.finfo(float).eps)
    # 200 samples miss cos = -1 by a little: y and z span just under 10
    np.testing.assert_allclose(spans, [1.0, 0.5, 0.5], atol=1e-3)
    V = GroupScaler(mode="per-dimension").fit_transform(demo)
    np.testing.assert_allclose(V.max(axis=0) - V.min(axis=0), 1.0)
    # the position group shares one range, distinct from velocity's
    s = GroupScaler().fit(demo)
    assert s.data_min_[0] == s.data_min_[1] == s.data_min_[2] == -10.0
    assert s.data_max_[0] == s.data_max_[1] == s.data_max_[2] == 10.0
    assert s.group_min_["position"] == -10.0 and s.group_max_["position"] == 10.0
    assert s.column_groups_ == ("position",) * 3 + ("velocity",) * 3
    assert s.group_names_ == ("position", "velocity")
    assert s.columns_ == ("x", "y", "z", "vx", "vy", "vz")
    np.testing.assert_array_equal(s.column_weights_, np.ones(6))
    assert s.n_features_in_ == 6 and s.n_samples_seen_ == 200


def test_against_reference_on_ragged_list():
    rng = np.random.default_rng(0)
    arrays = [rng.normal(size=(n, 4)) * [1, 5, 0.1, 2] for n in (3, 10, 7)]
    groups = ["a", "a", "b", "c"]
    s = GroupScaler(groups, weights={"b": 2.5})
    got = s.fit_transform(arrays)
    assert isinstance(got, list) and [g.shape for g in got] == [a.shape for a in arrays]
    ref = _reference_group_normalize(arrays, groups, {"b": 2.5})
    for g, r in zip(got, ref, strict=True):
        np.testing.assert_allclose(g, r, rtol=1e-14, atol=1e-14)
    back = s.inverse_transform(got)
    for b, a in zip(back, arrays, strict=True):
        np.testing.assert_allclose(b, a, rtol=1e-12, atol=1e-12)


def test_fit_on_list_of_ragged_demonstrations():
    demos = [_spiral_demo(50), _spiral_demo(80, 2.0)]
    s = GroupScaler().fit(demos)
    assert s.group_min_["position"] == -20.0 and s.group_max_["position"] == 20.0
    U = s.transform(demos)
    assert [u.shape for u in U] == [(50, 6), (80, 6)]
    np.testing.assert_allclose(U[0][:, 0].max(), 0.75)


def test_zero_range_group_maps_to_zero_and_back():
    X = np.column_stack([np.linspace(0, 4, 5), np.full(5, 7.0), np.full(5, 7.0)])
    s = GroupScaler(["p", "const", "const"]).fit(X)
    U = s.transform(X)
    assert np.all(np.isfinite(U))
    np.testing.assert_array_equal(U[:, 1:], 0.0)
    np.testing.assert_array_equal(s.data_range_, [4.0, 0.0, 0.0])
    np.testing.assert_array_equal(s.inverse_transform(U), X)
    for mode in ("per-dimension", "group"):
        s2 = GroupScaler(["p", "q", "r"], mode=mode).fit(X)
        np.testing.assert_array_equal(s2.transform(X)[:, 1:], 0.0)


def test_out_of_range_values_are_kept():
    s = GroupScaler(["p", "p"]).fit(np.array([[0.0, 0.0], [10.0, 5.0]]))
    U = s.transform(np.array([[-5.0, 20.0]]))
    np.testing.assert_array_equal(U, [[-0.5, 2.0]])
    np.testing.assert_array_equal(s.inverse_transform(U), [[-5.0, 20.0]])


def test_weights_dict_sequence_and_unweighted_view():
    X = np.array([[0.0, 0.0, 1.0], [2.0, 1.0, 3.0]])
    s = GroupScaler(["p", "p", "v"], weights={"v": 3.0}).fit(X)
    np.testing.assert_array_equal(s.column_weights_, [1.0, 1.0, 3.0])
    np.testing.assert_array_equal(s.transform(X), [[0, 0, 0], [1, 0.5, 3]])
    np.testing.assert_array_equal(
        s.transform(X, weighted=False), [[0, 0, 0], [1, 0.5, 1]]
    )
    np.testing.assert_array_equal(s.inverse_transform([[1, 0.5, 3]]), [[2, 1, 3]])
    np.testing.assert_array_equal(
        s.inverse_transform([[1, 0.5, 1]], weighted=False), [[2, 1, 3]]
    )
    s2 = GroupScaler(["p", "p", "v"], weights=[1, 2, 0.5]).fit(X)
    np.testing.assert_array_equal(s2.transform(X)[1], [1, 1, 0.5])


def test_zero_weight_inverse_gives_the_minimum():
    X = np.array([[0.0, 1.0], [2.0, 3.0]])
    s = GroupScaler(["p", "v"], weights={"v": 0}).fit(X)
    U = s.transform(X)
    np.testing.assert_array_equal(U[:, 1], 0.0)
    np.testing.assert_array_equal(s.inverse_transform(U), [[0.0, 1.0], [2.0, 1.0]])


def test_mode_none_is_identity_with_weights():
    X = np.array([[0.0, -3.0], [2.0, 30.0]])
    s = GroupScaler(["p", "v"], mode="none").fit(X)
    np.testing.assert_array_equal(s.transform(X), X)
    np.testing.assert_array_equal(s.data_min_, [0, 0])
    np.testing.assert_array_equal(s.data_max_, [1, 1])
    s = GroupScaler(["p", "v"], mode="none", weights={"v": 2}).fit(X)
    np.testing.assert_array_equal(s.transform(X), [[0, -6], [2, 60]])


@settings(max_examples=60, deadline=None)
@given(
    st.lists(
        hnp.arrays(
            np.float64,
            st.tuples(st.integers(1, 12), st.just(3)),
            elements=st.floats(-1e6, 1e6, allow_nan=False),
        ),
        min_size=1,
        max_size=4,
    ),
    st.sampled_from(["group", "per-dimension", "none"]),
    st.lists(st.floats(0.1, 10), min_size=3, max_size=3),
)
def test_round_trip_property(arrays, mode, weights):
    s = GroupScaler(["a", "a", "b"], mode=mode, weights=weights).fit(arrays)
    U = s.transform(arrays)
    back = s.inverse_transform(U)
    for a, b in zip(arrays, back, strict=True):
        np.testing.assert_allclose(b, a, rtol=1e-9, atol=1e-9 * (1 + np.abs(a).max()))
    if mode != "none":
        lo = np.min([u.min(axis=0) for u in U], axis=0)
        hi = np.max([u.max(axis=0) for u in U], axis=0)
        assert np.all(lo >= -1e-12) and np.all(hi <= np.array(weights) * (1 + 1e-12))


def test_estimator_contract():
    s = GroupScaler(groups=["p"], mode="group", weights=None)
    assert s.get_params() == {"groups": ["p"], "mode": "group", "weights": None}
    assert not hasattr(s, "data_min_")
    assert s.fit(np.zeros((2, 1))) is s
    assert s.set_params(mode="none") is s and s.mode == "none"
    with pytest.raises(ValidationError, match="unknown parameter 'foo'"):
        s.set_params(foo=1)
    assert repr(s) == "GroupScaler(groups=['p'], mode='none', weights=None)"
    with pytest.raises(NotFittedError, match="not fitted yet; call fit"):
        GroupScaler(["p"]).transform(np.zeros((2, 1)))
    with pytest.raises(NotFittedError):
        GroupScaler(["p"]).inverse_transform(np.zeros((2, 1)))


def test_transform_checks_columns():
    demo = _spiral_demo(20)
    s = GroupScaler().fit(demo)
    with pytest.raises(
        ValidationError, match=r"expected the fitted columns .* demo\.select"
    ):
        s.transform(demo.select("position"))
    renamed = Demonstration(
        demo.t, demo.X, [c + "_" for c in demo.columns], demo.groups
    )
    with pytest.raises(ValidationError, match="expected the fitted columns"):
        s.transform(renamed)
    with pytest.raises(
        ValidationError,
        match=r"X must have 6 columns \(as in fit\); got shape \(20, 3\)",
    ):
        s.transform(np.zeros((20, 3)))
    np.testing.assert_array_equal(s.transform(demo), s.transform(np.asarray(demo.X)))
    a = GroupScaler(["position"] * 3 + ["velocity"] * 3).fit(np.asarray(demo.X))
    regrouped = Demonstration(demo.t, demo.X, demo.columns, ["g"] * 6)
    with pytest.raises(ValidationError, match="fitted groups"):
        a.transform(regrouped)
    np.testing.assert_array_equal(a.transform(demo), s.transform(demo))


@pytest.mark.parametrize(
    ("scaler", "data", "error", "match"),
    [
        (
            GroupScaler(),
            np.zeros((3, 2)),
            ValidationError,
            r"groups must be given .* got groups=None",
        ),
        (
            GroupScaler(["p"]),
            np.zeros((3, 2)),
            ValidationError,
            "group of each of the 2 columns",
        ),
        (
            GroupScaler("pp"),
            np.zeros((3, 2)),
            ValidationError,
            "groups must be a sequence",
        ),
        (
            GroupScaler(["p"], mode="minmax"),
            np.zeros((3, 1)),
            OptionError,
            "unknown mode 'minmax'; expected one of: 'group', 'per-dimension', 'none'",
        ),
        (GroupScaler(["p"]), [], ValidationError, "at least one demonstration"),
        (
            GroupScaler(["p"]),
            [np.zeros((2, 1)), np.zeros((2, 2))],
            ValidationError,
            r"same number of columns \(1, as demos\[0\]\); got 2 in demos\[1\]",
        ),
        (
            GroupScaler(["p"]),
            [np.zeros((2, 1)), np.full((2, 1), np.nan)],
            ValidationError,
            r"demos\[1\] must be finite",
        ),
        (GroupScaler(["p"]), np.zeros((0, 1)), ValidationError, "at least 1 row"),
        (
            GroupScaler(["p"]),
            np.zeros(3),
            ValidationError,
            r"shape \(n_points, n_dims\)",
        ),
        (
            GroupScaler(["p", "v"], weights={"q": 1}),
            np.zeros((2, 2)),
            ValidationError,
            r"weights name unknown group\(s\) \['q'\]",
        ),
        (
            GroupScaler(["p", "v"], weights={"v": -1}),
            np.zeros((2, 2)),
            ValidationError,
            "weights must be finite numbers >= 0; got -1 for column 1",
        ),
        (
            GroupScaler(["p", "v"], weights=[1, np.nan]),
            np.zeros((2, 2)),
            ValidationError,
            "finite numbers >= 0; got nan",
        ),
        (
            GroupScaler(["p", "v"], weights=[1]),
            np.zeros((2, 2)),
            ValidationError,
            r"one entry per column \(length 2\)",
        ),
        (
            GroupScaler(["p", "v"], weights="heavy"),
            np.zeros((2, 2)),
            ValidationError,
            "weights must be a mapping",
        ),
        (
            GroupScaler(["p", "p", "p", "v", "v", "v"]),
            _spiral_demo(5),
            ValidationError,
            "disagrees with the demonstrations' groups",
        ),
        (
            GroupScaler(),
            [_spiral_demo(5), _spiral_demo(5).select("position")],
            ValidationError,
            r"demos\[1\] has columns .* expected the columns of demos\[0\]",
        ),
        (
            GroupScaler(),
            [_spiral_demo(5), np.zeros((5, 6))],
            ValidationError,
            r"mixes Demonstrations and arrays; got ndarray at demos\[1\]",
        ),
        (GroupScaler(), "abc", ValidationError, "real numbers"),
    ],
)
def test_fit_errors(scaler, data, error, match):
    with pytest.raises(error, match=match):
        scaler.fit(data)


def test_from_ranges_reproduces_a_fitted_scaler():
    rng = np.random.default_rng(5)
    q = rng.normal(size=(30, 4))
    q /= np.linalg.norm(q, axis=1, keepdims=True)
    demo = Demonstration.from_arrays(
        np.arange(30.0), position=rng.normal(size=(30, 2)) * 7, orientation=q
    )
    for mode in ("group", "per-dimension", "none"):
        s = GroupScaler(mode=mode, weights={"orientation": 0.5}).fit(demo)
        r = GroupScaler.from_ranges(
            s.data_min_,
            s.data_max_,
            s.column_groups_,
            columns=s.columns_,
            mode=mode,
            weights={"orientation": 0.5},
        )
        np.testing.assert_array_equal(r.transform(demo), s.transform(demo))
        U = s.transform(demo)
        np.testing.assert_array_equal(r.inverse_transform(U), s.inverse_transform(U))
        assert r.group_min_ == s.group_min_ or mode != "group"
        assert r.get_params()["mode"] == mode


@pytest.mark.parametrize(
    ("args", "kwargs", "match"),
    [
        (([0.0, 1.0], [1.0], ["p", "p"]), {}, r"data_max must have shape \(2,\)"),
        (
            ([0.0, 2.0], [1.0, 1.0], ["p", "p"]),
            {},
            "data_max must be >= data_min; got 1.0 < 2.0 in column 1",
        ),
        (([0.0], [np.nan], ["p"]), {}, "data_max must be finite"),
        (
            ([0.0, 0.0], [1.0, 1.0], ["p"]),
            {},
            "column_groups must name the group of each of the 2",
        ),
        (([0.0, 0.0], [1.0, 1.0], "pp"), {}, "column_groups must name"),
        (
            ([0.0], [1.0], ["p"]),
            {"columns": ["a", "b"]},
            "columns must have 1 names; got 2",
        ),
        (
            ([0.0], [1.0], ["p"]),
            {"weights": {"p": -1}},
            "weights must be finite numbers >= 0",
        ),
    ],
)
def test_from_ranges_errors(args, kwargs, match):
    with pytest.raises(ValidationError, match=match):
        GroupScaler.from_ranges(*args, **kwargs)
    with pytest.raises(OptionError, match="unknown mode"):
        GroupScaler.from_ranges([0.0], [1.0], ["p"], mode="x")


def test_subnormal_range_counts_as_zero_range():
    # found by hypothesis: 1 / 2.2e-313 overflows; such a range is no range
    X = np.array([[0.0, 2.22507386e-313, 2.22507386e-313], [0.0, 0.0, 0.0]])
    s = GroupScaler(["a", "a", "b"]).fit(X)
    U = s.transform(X)
    assert np.all(np.isfinite(U)) and np.all(np.abs(U) < 1e-300)
    np.testing.assert_array_equal(s.inverse_transform(U), X)
    np.testing.assert_array_equal(s.transform(X + 1.0), np.ones_like(X))


@pytest.mark.parametrize("mode", ["group", "per-dimension", "none"])
def test_from_data_ranges_is_fit_on_data_with_those_extremes(mode):
    rng = np.random.default_rng(4)
    parts = [rng.normal(size=(n, 3)) * [1.0, 5.0, 0.1] for n in (7, 3, 11)]
    groups = ["p", "p", "f"]
    want = GroupScaler(groups, mode=mode, weights={"f": 2.0}).fit(parts)
    got = GroupScaler.from_data_ranges(
        np.min([a.min(axis=0) for a in parts], axis=0),
        np.max([a.max(axis=0) for a in parts], axis=0),
        groups, n_samples=21, mode=mode, weights={"f": 2.0},
    )  # fmt: skip
    assert vars(got).keys() == vars(want).keys()
    assert got.groups is None  # not a parameter: rebuilt from fitted state
    for k, v in vars(want).items():
        g = vars(got)[k]
        if k != "groups":
            assert np.array_equal(g, v) if isinstance(v, np.ndarray) else g == v, k
    # from_ranges takes the data's extremes and sample count back
    again = GroupScaler.from_ranges(
        want.data_min_, want.data_max_, groups, mode=mode, weights={"f": 2.0},
        group_min=want.group_min_, group_max=want.group_max_, n_samples_seen=21,
    )  # fmt: skip
    for k, v in vars(want).items():
        g = vars(again)[k]
        if k != "groups":
            assert np.array_equal(g, v) if isinstance(v, np.ndarray) else g == v, k
    with pytest.raises(ValidationError, match="must name the groups"):
        GroupScaler.from_ranges([0.0], [1.0], ["p"], group_min={"q": 0.0})


def test_inverse_scale_maps_spreads_without_the_offset():
    s = GroupScaler(["p", "p", "c"]).fit(np.array([[10.0, 0.0, 3.0], [30.0, 5.0, 3.0]]))
    D = np.array([[0.5, 0.25, 0.5]])
    # a spread of half the range is half the range; a constant column keeps it
    np.testing.assert_array_equal(s.inverse_scale(D), [[15.0, 7.5, 0.5]])
    np.testing.assert_allclose(
        s.inverse_scale(D)[:, :2],
        (s.inverse_transform(D) - s.inverse_transform(np.zeros((1, 3))))[:, :2],
    )
    with pytest.raises(NotFittedError):
        GroupScaler(["p"]).inverse_scale([[1.0]])


@settings(max_examples=60, deadline=None)
@given(st.integers(0, 2**32 - 1), st.integers(1, 40), st.integers(1, 13), st.booleans())
def test_transform_is_the_numpy_formula(seed, n, d, weighted):
    # the compiled transform (tiles of d * 8 values and the rest) against the
    # numpy expression it replaced
    rng = np.random.default_rng(seed)
    X = rng.normal(0, 10, (n, d + 1))
    X[:, d] = 2.5  # a zero range: divided by 1
    groups = [f"g{k}" for k in np.sort(rng.integers(0, 3, d))] + ["z"]
    scaler = GroupScaler(groups, weights={groups[0]: 0.3, "z": 2.0}).fit(X)
    div = np.where(scaler.data_range_ > np.finfo(float).tiny, scaler.data_range_, 1.0)
    w = scaler.column_weights_ if weighted else 1.0
    Y = X * 1.5 - 1.0  # partly outside the fitted range
    got = scaler.transform(Y, weighted=weighted)
    want = (Y - scaler.data_min_) / div * w
    assert got.tobytes() == want.tobytes()
    # a view with strides (a column slice) gives the same
    wide = np.column_stack([Y, Y])[:, : d + 1]
    assert scaler.transform(wide, weighted=weighted).tobytes() == want.tobytes()
