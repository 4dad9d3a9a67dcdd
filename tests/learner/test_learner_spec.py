"""The demonstration spec: groups, levels, the scaler of pass 1, one reduction."""

import numpy as np
import pytest
from hypothesis import given, settings
from hypothesis import strategies as st

from learner_helpers import (
    waves,
)
from ndlfd import (
    Demonstration,
    KeypointHMM,
    ValidationError,
    simplify,
    synth,
)
from ndlfd.demonstration import unit_time
from ndlfd.learner import (
    AUTO_GROUPS,
    DEFAULT_LEVELS,
    RangeStats,
    resolve_groups,
)
from ndlfd.learner._spec import (
    DemoSpec,
    levels_by_group,
    prepare,
    scaler_from_ranges,
)
from ndlfd.normalize import GroupScaler


def _demo(**groups):
    t = np.linspace(0.0, 1.0, 30)
    return Demonstration.from_arrays(t, **groups)


def test_resolve_groups_auto_none_and_names():
    d = _demo(position=np.zeros((30, 2)), force=np.ones((30, 1)))
    assert resolve_groups("auto", d) == ("position", "velocity", "force")
    assert resolve_groups("auto", d, derive_velocity=False) == ("position", "force")
    assert resolve_groups(None, d) == ("position", "force")
    assert resolve_groups("force", d) == ("force",)
    assert resolve_groups(["force", "position"], d) == ("force", "position")
    other = _demo(gripper=np.zeros((30, 1)))
    assert resolve_groups("auto", other) == ("gripper",)  # none of AUTO_GROUPS
    # every group is learned: those of AUTO_GROUPS first, then the others
    arm = _demo(joints=np.zeros((30, 5)), gripper=np.zeros((30, 1)))
    assert resolve_groups("auto", arm) == ("gripper", "joints")
    mixed = _demo(tool=np.zeros((30, 1)), position=np.zeros((30, 2)))
    assert resolve_groups("auto", mixed) == ("position", "velocity", "tool")
    assert set(AUTO_GROUPS) >= {"position", "velocity"}
    with pytest.raises(ValidationError, match="must not repeat"):
        resolve_groups(["position", "position"], d)
    with pytest.raises(ValidationError, match="non-empty sequence"):
        resolve_groups([], d)


def test_prepare_derives_velocity_and_names_what_is_missing():
    d = _demo(position=np.column_stack([np.linspace(0, 1, 30), np.zeros(30)]))
    p = prepare(d, ("position", "velocity"))
    assert p.group_names == ("position", "velocity")
    with pytest.raises(ValidationError, match=r"lacks group.*velocity"):
        prepare(d, ("position", "velocity"), derive_velocity=False)
    with pytest.raises(ValidationError, match="--group force=NAME"):
        prepare(d, ("force",), cli=True)


def test_levels_by_group():
    groups = ("position", "velocity")
    assert levels_by_group(None, groups) == {g: DEFAULT_LEVELS[g] for g in groups}
    assert levels_by_group(7, groups) == {"position": 7, "velocity": 7}
    with pytest.raises(ValidationError, match="not learned"):
        levels_by_group({"force": 3}, groups)
    # any group has levels: joints like position, a user group OTHER_LEVELS
    assert levels_by_group(None, ("joints", "x")) == {"joints": 20, "x": 10}
    assert levels_by_group({"x": 3}, ("joints", "x")) == {"joints": 20, "x": 3}


@pytest.mark.parametrize("mode", ["group", "per-dimension", "none"])
def test_the_scaler_from_ranges_is_groupscalers_fit(mode):
    train, _ = synth.make_dataset("square", n_demos=4, random_state=0)
    parts = [RangeStats.of(i, d.X) for i, d in enumerate(train)]
    ranges = parts[0].merge(*parts[1:])
    got = scaler_from_ranges(
        ranges, train[0].columns, train[0].groups, normalization=mode,
        weights={"velocity": 0.5},
    )  # fmt: skip
    want = GroupScaler(mode=mode, weights={"velocity": 0.5}).fit(train)
    assert vars(got).keys() == vars(want).keys()
    for k, v in vars(want).items():
        g = vars(got)[k]
        assert np.array_equal(g, v) if isinstance(v, np.ndarray) else g == v, k


def test_one_reduction_serves_fit_and_timing():
    train, test = synth.make_dataset("square", n_demos=6, random_state=1)
    m = KeypointHMM(epsilon=0.1, n_time_bins=20).fit(train)
    spec = DemoSpec(
        groups=m.groups_, columns=m.columns_, col_groups=m.column_groups_,
        epsilon=m.epsilon, scaler=m.scaler_, codebook=m.codebook_,
        time_bins=m.time_bins_,
    )  # fmt: skip
    d = spec.prepared(train[2])
    r = spec.reduce(d)
    # the fit kept exactly these key points for this demonstration
    np.testing.assert_array_equal(r.keypoints, m.keypoints_[2])
    np.testing.assert_array_equal(
        r.keypoints, simplify(m.scaler_.transform(d, weighted=False), 0.1)
    )
    np.testing.assert_array_equal(r.values, m.scaler_.transform(d, weighted=False))
    np.testing.assert_array_equal(r.key_bins, m.time_bins_.transform(d.t)[r.keypoints])
    assert r.tau.tobytes() == m.time_bins_.normalize(d.t).tobytes()
    e = spec.encode(d)
    ids = m.fit_stats_.keypoint_lists()[1][2]  # interned: their cells are the keys'
    np.testing.assert_array_equal(e.key_cells, m.centroid_cells_[ids])
    np.testing.assert_array_equal(e.key_cells, m.codebook_.cells(r.values[r.keypoints]))
    np.testing.assert_array_equal(e.key_bins, r.key_bins)
    # and the paper's timing of a demonstration is the same reduction
    key_t, symbols, _ = m.timing(test)
    rt = spec.reduce(spec.prepared(test))
    np.testing.assert_array_equal(key_t, test.t[rt.keypoints])
    np.testing.assert_array_equal(symbols, rt.key_bins)
    with pytest.raises(ValidationError, match="same columns"):
        spec.prepared(_demo(position=np.zeros((30, 3))))


def test_after_scan_sees_the_ranges_and_sets_parameters_for_pass_two():
    train, test = synth.make_dataset("square", n_demos=6, random_state=1)
    seen = []

    def after_scan(ranges):
        seen.append((ranges.n_demos, ranges.min_samples, ranges.n_samples))
        return {"n_time_bins": 17, "n_points": 9}

    m = KeypointHMM(epsilon=0.1, n_time_bins=40).fit(train, after_scan=after_scan)
    n = [d.n_samples for d in train]
    assert seen == [(6, min(n), sum(n))]
    assert m.n_time_bins == 17 and m.time_bins_.n_bins == 17
    ref = KeypointHMM(epsilon=0.1, n_time_bins=17, n_points=9).fit(train)
    np.testing.assert_array_equal(m.generate(test.t).X, ref.generate(test.t).X)
    assert m.fit_stats_ == ref.fit_stats_
    # None (or an empty dict) changes nothing; bad values are refused as in fit
    same = KeypointHMM(epsilon=0.1, n_time_bins=17).fit(
        train, after_scan=lambda r: None
    )
    assert same.n_time_bins == 17
    with pytest.raises(ValidationError, match="n_time_bins"):
        KeypointHMM().fit(train, after_scan=lambda r: {"n_time_bins": 0})
    with pytest.raises(ValidationError, match="n_points must be between 2 and"):
        KeypointHMM().fit(train, after_scan=lambda r: {"n_points": 10**6})


def test_the_scaler_is_groupscalers_fit_exactly():
    demos = [Demonstration.from_arrays(t, position=P) for t, P in waves(9)]
    for mode in ("group", "per-dimension", "none"):
        m = KeypointHMM(normalization=mode, weights={"velocity": 0.5}).fit(demos)
        prepared = [prepare(d, m.groups_) for d in demos]
        ref = GroupScaler(mode=mode, weights={"velocity": 0.5}).fit(prepared)
        got, want = vars(m.scaler_), vars(ref)
        assert got.keys() == want.keys()
        for k, v in want.items():
            assert np.array_equal(got[k], v) if isinstance(v, np.ndarray) else (
                got[k] == v), k  # fmt: skip


@settings(max_examples=60, deadline=None)
@given(st.integers(0, 2**32 - 1), st.integers(1, 60), st.booleans())
def test_unit_time_of_the_key_points_is_theirs_in_the_whole(seed, n, uniform):
    # the key points keep both ends, so the fit bins the unit time of the
    # key points' stamps: bit for bit the whole demonstration's at them
    rng = np.random.default_rng(seed)
    steps = np.full(n - 1, 0.01) if uniform else rng.uniform(1e-3, 2.0, n - 1)
    t = rng.uniform(-1e3, 1e3) + np.concatenate([[0.0], np.cumsum(steps)])
    inner = rng.choice(np.arange(1, n - 1), size=rng.integers(0, max(n - 1, 1)))
    idx = np.unique(np.r_[0, inner, n - 1]).astype(np.int64)
    assert unit_time(t[idx]).tobytes() == unit_time(t)[idx].tobytes()


@pytest.mark.parametrize("n_jobs", [1, 2])
def test_demonstrations_given_as_minus_q_fit_the_same_model(n_jobs):
    # q and -q are one rotation: a recording on the other side of the sphere
    # must not be averaged with the others into rotations none of them made
    # (before: 180 degrees off the model of the same data on one side)
    from test_learner_generation import carries

    demos = carries()
    q = demos[0].columns_of("orientation")
    flipped = []
    for i, d in enumerate(demos):
        X = d.X.copy()
        if i % 2:
            X[:, q] = -X[:, q]
        flipped.append(Demonstration(d.t, X, d.columns, d.groups, d.frames))
    t = np.linspace(0.0, demos[0].t[-1], 101)
    paths = [
        KeypointHMM(n_jobs=n_jobs).fit(ds).generate(t, dense=True)
        for ds in (demos, flipped)
    ]
    np.testing.assert_array_equal(paths[0].X, paths[1].X)
    # and the first demonstration decides the side: all of them negated,
    # the path is negated
    negated = [
        Demonstration(d.t, np.where(np.isin(np.arange(d.X.shape[1]), q), -d.X, d.X),
                      d.columns, d.groups, d.frames)
        for d in demos
    ]  # fmt: skip
    other = KeypointHMM(n_jobs=n_jobs).fit(negated).generate(t, dense=True)
    np.testing.assert_allclose(other.get("orientation"), -paths[0].get("orientation"),
                               atol=1e-12)  # fmt: skip
