"""Task frames keep what the demonstrations do in the world (issue 39).

A pick-and-place around a fixed post (:mod:`frames_obstacle`): the hand
passes the post in the world's frame and grasps an object whose pose varies.
With the object's frame given, the path keeps the demonstrations' clearance
to the post (at least 0.8 times their smallest) and still grasps the object.
The views' covariances are shrunk (:func:`shrunk_covariance`, checked here
against the paper's formula written out entry by entry): a route of three or
four templates gave views whose chance flat directions the product of
Gaussians followed into the post (0.64x and 0.69x of the clearance on the
pose grid below; replanning on such a route, paths through the post and
58-81 mm off the grasp).
"""

import numpy as np
import pytest
from hypothesis import given, settings
from hypothesis import strategies as st
from hypothesis.extra.numpy import arrays
from scipy.spatial.transform import Rotation

from frames_obstacle import OBJECT, clearance, grasp_error, pick_around
from ndlfd import Demonstration, KeypointHMM
from ndlfd.learner._frame_mix import shrunk_covariance


def _oas_reference(S, n):
    """Chen et al. (2010), eq. 23, with plain loops over the entries."""
    k = len(S)
    tr = sum(S[i][i] for i in range(k))
    tr2 = sum(S[i][j] * S[j][i] for i in range(k) for j in range(k))
    den = (n + 1 - 2 / k) * (tr2 - tr * tr / k)
    rho = 1.0 if den <= 1e-12 * max(tr2, 1e-300) else min(
        1.0, ((1 - 2 / k) * tr2 + tr * tr) / den
    )  # fmt: skip
    return [
        [(1 - rho) * S[i][j] + (rho * tr / k if i == j else 0.0) for j in range(k)]
        for i in range(k)
    ]


@settings(max_examples=60, deadline=None)
@given(
    arrays(np.float64, (7, 3), elements=st.floats(-1, 1)),
    st.integers(2, 7),
    st.integers(1, 3),
)
def test_shrinkage_is_the_oas_formula(X, n, k):
    X = X[:n, :k]
    D = X - X.mean(axis=0)
    S = D.T @ D / n
    got = shrunk_covariance(S[None], float(n))[0]
    np.testing.assert_allclose(got, _oas_reference(S.tolist(), n), atol=1e-12)
    # the trace (total spread) is kept, and it stays positive semi-definite
    assert np.trace(got) == pytest.approx(np.trace(S), abs=1e-12)
    assert np.linalg.eigvalsh(got).min() > -1e-12


def test_shrinkage_fades_with_many_samples():
    rng = np.random.default_rng(0)
    X = rng.normal(size=(4000, 3)) * [1.0, 0.3, 0.1]
    S = np.cov(X.T, bias=True)
    got = shrunk_covariance(S, 4000.0)
    np.testing.assert_allclose(got, S, atol=2e-3 * np.trace(S))
    # three samples in 3-D span a plane: shrunk, no direction is certain
    few = np.cov(X[:3].T, bias=True)
    assert np.linalg.eigvalsh(few).min() < 1e-12
    assert np.linalg.eigvalsh(shrunk_covariance(few, 3.0)).min() > 0.05 * np.trace(few)


def _quat_down(yaw):
    r = Rotation.from_euler("z", yaw) * Rotation.from_euler("x", np.pi)
    return np.roll(r.as_quat(), 1)


POSES = [
    (dx, dy, yaw)
    for dx in (-0.1, 0.0, 0.1)
    for dy in (-0.1, 0.0, 0.1)
    for yaw in np.radians([-30, 30])
]


@pytest.mark.parametrize(("n", "n_right"), [(8, 3), (10, 4)])
def test_the_path_keeps_the_clearance_on_two_routes(n, n_right):
    # the route followed from home has 5 or 6 templates; before the shrinkage
    # 3 and 2 of these 18 poses came within 0.64x and 0.69x
    demos, _ = pick_around(n, n_right=n_right, random_state=0)
    smallest = min(clearance(d.get("position")) for d in demos)
    model = KeypointHMM().fit(demos)
    t = demos[0].t
    start = {"position": demos[0].get("position")[0]}
    for dx, dy, yaw in POSES:
        o = OBJECT + [dx, dy, 0.0]
        pose = np.concatenate([o, _quat_down(yaw)])
        path = model.generate(t, dense=True, frames={"object": pose}, start=start)
        P = path.get("position")
        assert clearance(P) >= 0.8 * smallest, (dx, dy, yaw, clearance(P), smallest)
        assert grasp_error(P, o) < 5e-3  # measured up to 3.3 mm


@pytest.fixture(scope="module")
def two_routes():
    return pick_around(14, n_right=4, random_state=0)[0]


@pytest.mark.parametrize("k", [0, 5, 13])
def test_held_out_grasps_and_clearance_on_two_routes(two_routes, k):
    demos = two_routes
    test, train = demos[k], demos[:k] + demos[k + 1 :]
    smallest = min(clearance(d.get("position")) for d in train)
    model = KeypointHMM().fit(train)
    P0 = test.get("position")
    path = model.generate(test.t, dense=True, frames=dict(test.frames),
                          start={"position": P0[0]})  # fmt: skip
    P = path.get("position")
    assert clearance(P) >= 0.8 * smallest
    assert grasp_error(P, test.frames["object"]) < 3e-3


@pytest.mark.parametrize("k", [10, 11, 12, 13])
def test_replanning_on_the_minor_route_keeps_to_it(two_routes, k):
    # held out from the 4 that go out on the right: the prefix (a fifth of
    # the motion, before the post) leaves 3 templates on that route. Before
    # the shrinkage two of these folds crossed to the left through the post
    # (0.28x and 0.30x of the clearance) and three missed the grasp by 58-81
    # mm; now 1.15-1.34x and at most 1.3 mm
    demos = two_routes
    test, train = demos[k], demos[:k] + demos[k + 1 :]
    smallest = min(clearance(d.get("position")) for d in train)
    model = KeypointHMM().fit(train)
    cut = test.n_samples // 5
    pre = Demonstration(test.t[:cut], test.X[:cut], test.columns, test.groups)
    path = model.generate(test.t, dense=True, frames=dict(test.frames),
                          observed=pre)  # fmt: skip
    P = path.get("position")
    assert P[int(0.25 * len(P)), 1] < 0  # out on the right, as the prefix went
    assert clearance(P) >= 0.8 * smallest
    assert grasp_error(P, test.frames["object"]) < 5e-3
