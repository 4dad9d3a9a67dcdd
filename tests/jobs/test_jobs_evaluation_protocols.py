import math

import numpy as np
import pytest
from hypothesis import given, settings
from hypothesis import strategies as st

from ndlfd import Demonstration, ValidationError
from ndlfd.jobs._evaluation_protocols import (
    METRICS,
    PREFIX_FRACTION,
    PROTOCOLS,
    score,
)
from ndlfd.metrics import (
    discrete_frechet,
    dtw_distance,
    endpoint_error,
    path_length_ratio,
    time_aligned_rmse,
    turning_ratio,
)


def _demo(n, seed=0, shift=0.0):
    rng = np.random.default_rng(seed)
    t = np.cumsum(rng.uniform(0.5, 1.5, n))
    s = np.linspace(0, 3, n)
    P = np.column_stack([np.cos(s), np.sin(2 * s)]) * 5 + shift
    return Demonstration.from_arrays(t, position=P + rng.normal(0, 0.05, (n, 2)))


def test_each_protocol_gives_what_it_says():
    test = _demo(41)
    P, t = test.get("position"), test.t
    assert PROTOCOLS.get("time").conditions(test) == ({}, 0)
    kw, first = PROTOCOLS.get("time+start").conditions(test)
    assert first == 0 and list(kw) == ["start"]
    np.testing.assert_array_equal(kw["start"], P[0])
    kw, first = PROTOCOLS.get("via").conditions(test)
    assert first == 0 and sorted(kw) == ["start", "via"]
    (when, where), *more = kw["via"]
    assert not more and when == t[20]
    np.testing.assert_array_equal(where, P[20])
    kw, first = PROTOCOLS.get("prefix").conditions(test)
    assert list(kw) == ["observed"] and first == math.ceil(PREFIX_FRACTION * 41) == 13
    np.testing.assert_array_equal(kw["observed"], P[:13])
    # two samples: one observed, one generated
    kw, first = PROTOCOLS.get("prefix").conditions(_demo(2))
    assert first == 1 and kw["observed"].shape == (1, 2)
    # the start, the grasp (42 % of the samples: 0.42 * 40 = 16.8 -> 17), the goal
    kw, first = PROTOCOLS.get("task").conditions(test)
    assert first == 0 and sorted(kw) == ["start", "via"]
    np.testing.assert_array_equal(kw["start"], P[0])
    assert [w for w, _ in kw["via"]] == [t[17], t[40]]
    np.testing.assert_array_equal(np.array([p for _, p in kw["via"]]), P[[17, 40]])


def test_the_pick_and_place_sets_are_the_synthetic_ones():
    from ndlfd import synth
    from ndlfd.jobs._evaluation_protocols import TASK_SHAPES, load_shape, shape_group

    for name, yaw in TASK_SHAPES.items():
        demos = load_shape(name)
        want, _ = synth.pick_place(12, yaw=np.deg2rad(yaw), random_state=0)
        assert len(demos) == 12 and all(
            a == b for a, b in zip(demos, want, strict=True)
        )
        assert shape_group(name) == "task"


def test_evaluate_runs_the_task_protocol_on_a_pick_and_place_set():
    from ndlfd.jobs.evaluation import evaluate

    result = evaluate(["PickPlace"], generators=["ndlfd", "mean"], folds=2, n_jobs=1,
                      progress=False)  # fmt: skip
    assert result.protocols == ("time", "time+start", "via", "prefix", "task",
                                "frames")  # fmt: skip
    rows = [r for r in result.rows if r["protocol"] == "task"]
    assert len(rows) == 4 and all(r["ok"] and r["group"] == "task" for r in rows)
    # both pass through the grasp and the goal exactly
    assert all(r["via_error"] < 1e-9 for r in rows)
    # with the frames, ndlfd is given no via point: its grasp is where the
    # object's frame puts it (within 5 mm); the mean still gets the points
    framed = {r["generator"]: r for r in result.rows if r["protocol"] == "frames"}
    assert framed["mean"]["via_error"] < 1e-9
    assert 0 < framed["ndlfd"]["via_error"] * framed["ndlfd"]["range"] < 5e-3
    lasa = evaluate(["Line"], generators=["mean"], folds=1, n_jobs=1, progress=False)
    assert "task" not in lasa.protocols and "frames" not in lasa.protocols


def test_the_frames_protocol_gives_frames_to_who_takes_them():
    from ndlfd.baselines import KeypointHMMGenerator, make_baseline
    from ndlfd.jobs._evaluation_protocols import _given, load_shape

    test = load_shape("PickPlace")[0]
    kw, _ = PROTOCOLS.get("frames").conditions(test)
    assert set(kw) == {"start", "via", "frames"}
    np.testing.assert_array_equal(kw["frames"]["object"], test.frames["object"])
    assert set(_given(KeypointHMMGenerator(), kw)) == {"start", "frames"}
    assert set(_given(make_baseline("mean"), kw)) == {"start", "via"}


def _path(test, seed):
    rng = np.random.default_rng(seed)
    return test.get("position") + rng.normal(0, 0.3, (test.n_samples, 2))


@settings(max_examples=25, deadline=None)
@given(st.integers(4, 60), st.integers(0, 2**16))
def test_the_prefix_protocol_scores_only_the_rest(n, seed):
    test, train = _demo(n, seed), [_demo(n + 5, seed + 1 + i, i) for i in range(3)]
    kw, first = PROTOCOLS.get("prefix").conditions(test)
    path = _path(test, seed)
    got = score(test, test.t, path, 2.0, train, kw, first)
    # what happens before the first generated sample does not count
    garbage = path.copy()
    garbage[:first] = 1e6
    assert score(test, test.t, garbage, 2.0, train, kw, first) == got
    # each metric on the suffix alone, by the metrics' own functions
    A, B, t = test.get("position")[first:], path[first:], test.t[first:]
    assert got["dtw"] == dtw_distance(A, B, normalize=True) / 2.0
    assert got["frechet"] == discrete_frechet(A, B) / 2.0
    assert got["rmse"] == time_aligned_rmse(t, A, t, B) / 2.0
    assert got["endpoint"] == endpoint_error(A, B) / 2.0
    assert got["path_length_ratio"] == path_length_ratio(A, B)
    assert got["turning_ratio"] == turning_ratio(A, B)
    jump = np.hypot(*(path[first] - test.get("position")[first - 1])) / 2.0
    assert got["prefix_jump"] == pytest.approx(jump, rel=1e-12)
    assert math.isnan(got["via_error"])


def test_on_route_is_the_distance_to_the_nearest_training_demo_from_the_same_phase():
    test = _demo(50, 0)
    train = [_demo(80, 1, shift=10.0), test, _demo(60, 2, shift=-10.0)]
    P = test.get("position")
    got = score(test, test.t, P.copy(), 1.0, train, {}, 0)
    assert got["on_route"] == 0.0 and got["dtw"] == 0.0
    # without the held-out one among them: the nearest of the others, by hand
    others = [train[0], train[2]]
    got = score(test, test.t, P.copy(), 3.0, others, {}, 0)
    hand = [dtw_distance(d.get("position"), P, normalize=True) / 3.0 for d in others]
    assert got["on_route"] == min(hand)
    # from a later phase on: only the training samples from that phase on
    kw, first = PROTOCOLS.get("prefix").conditions(test)
    got = score(test, test.t, P.copy(), 1.0, train, kw, first)
    assert got["on_route"] == 0.0 and got["prefix_jump"] > 0


def test_the_via_error_is_the_distance_at_the_via_time():
    test = _demo(31)
    P, t = test.get("position"), test.t
    path = _path(test, 3)
    kw, _ = PROTOCOLS.get("via").conditions(test)
    got = score(test, t, path, 4.0, [test], kw)
    assert got["via_error"] == pytest.approx(np.hypot(*(path[15] - P[15])) / 4.0)
    assert math.isnan(got["prefix_jump"])
    # several via points: the largest miss
    kw = {"via": [(t[5], P[5]), (t[25], P[25] + [3.0, 4.0])]}
    got = score(test, t, P.copy(), 1.0, [test], kw)
    assert got["via_error"] == 5.0
    assert set(got) == set(METRICS) - {"seconds"}


def test_a_path_of_the_wrong_shape_is_refused():
    test = _demo(10)
    with pytest.raises(ValidationError, match=r"expected \(10, 2\)"):
        score(test, test.t, np.zeros((10, 3)), 1.0, [test], {})
