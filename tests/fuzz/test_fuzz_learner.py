"""Fuzz KeypointHMM.fit and generate on arbitrary arrays.

Demonstrations of any length (one sample to a few dozen), constant or huge
values, NaN or inf; parameters from the edge of their range; new timings
that are empty, decreasing, non-finite or of one sample; start and goal of
the wrong length or non-finite. Each call gives a finite path or one
:class:`ndlfd.NdlfdError`.
"""

import numpy as np
import pytest
from fuzz_helpers import BAD_OBJECTS, arrays_2d, check_outcome, finite_or_nasty
from hypothesis import HealthCheck, given, settings
from hypothesis import strategies as st

import ndlfd
from ndlfd import Demonstration, KeypointHMM

FUZZ = settings(
    max_examples=40, deadline=None, suppress_health_check=[HealthCheck.too_slow]
)


@st.composite
def demos(draw):
    """A list of 1..4 demonstrations of one width, or None (one was refused)."""
    d = draw(st.integers(1, 3))
    nasty = draw(st.integers(0, 4)) == 0  # NaN, inf, 1e300... one time in five
    out = []
    for _ in range(draw(st.integers(1, 4))):
        n = draw(st.integers(1, 20))
        X = draw(arrays_2d(min_rows=n, max_rows=n, min_cols=d, max_cols=d, nasty=nasty))
        step = draw(st.sampled_from([1.0, 0.01, 1e5]))
        demo = check_outcome(
            Demonstration.from_arrays, step * np.arange(1.0, n + 1), position=X
        )
        if demo is None:
            return None  # refused as a demonstration: tested there
        out.append(demo)
    return out


@st.composite
def params(draw):
    return {
        "epsilon": draw(st.sampled_from([0.0, 0.05, 0.3, 1e300, -1.0, np.nan])),
        "n_time_bins": draw(st.sampled_from([1, 2, 10, 50, 0, 2.5])),
        "levels": draw(st.sampled_from([1, 2, 20, 1000, {"position": 3}, 0])),
        "pseudo_emission": draw(st.sampled_from([0.0, 0.5])),
        "generation": draw(st.sampled_from(["blend", "paper", "blend", "nope"])),
        "decoder": draw(st.sampled_from(["viterbi", "map"])),
        "normalization": draw(st.sampled_from(["group", "per-dimension", "none"])),
        "derive_velocity": draw(st.booleans()),
        "n_jobs": 1,
    }


@st.composite
def timings(draw):
    kind = draw(st.sampled_from(["plain", "plain", "long", "nasty", "short"]))
    if kind == "plain":
        return np.linspace(0.0, draw(st.sampled_from([1.0, 1e-9, 1e9])), 15)
    if kind == "long":
        return np.linspace(0.0, 3.0, 400)
    if kind == "short":
        return np.zeros(draw(st.integers(0, 1)))
    t = np.sort(np.array(draw(st.lists(finite_or_nasty(), min_size=2, max_size=6))))
    return t[::-1] if draw(st.booleans()) else t


@FUZZ
@given(
    train=demos(),
    p=params(),
    times=timings(),
    dense=st.booleans(),
    cond=st.sampled_from([None, "start", "goal", "both", "wrong", "nan"]),
)
def test_fuzz_keypointhmm_fit_and_generate(train, p, times, dense, cond):
    if train is None:
        return
    model = check_outcome(KeypointHMM(**p).fit, train)
    if model is None:
        return
    assert model.n_demos_ == len(train)
    assert set(train[0].columns) <= set(model.columns_)  # and a derived velocity
    d = train[0].n_dims
    kw = {}
    if cond in ("start", "both"):
        kw["start"] = {"position": train[0].X[0]}
    if cond in ("goal", "both"):
        kw["goal"] = {"position": train[-1].X[-1]}
    if cond == "wrong":
        kw["start"] = {"position": np.zeros(d + 1)}
    if cond == "nan":
        kw["goal"] = {"position": np.full(d, np.nan)}
    path = check_outcome(model.generate, times, dense=dense, **kw)
    if path is None:
        return
    assert isinstance(path, Demonstration) and path.columns == model.columns_
    if dense:
        np.testing.assert_array_equal(path.t, times)
    else:  # key points at times within the new timing
        assert times[0] <= path.t[0] and path.t[-1] <= times[-1]


@pytest.mark.parametrize("bad", [*BAD_OBJECTS, [np.zeros((3, 2))], [None]], ids=repr)
def test_fuzz_keypointhmm_fit_wrong_types(bad):
    assert check_outcome(KeypointHMM(n_jobs=1).fit, bad) is None


@pytest.mark.parametrize("bad", BAD_OBJECTS, ids=repr)
def test_fuzz_keypointhmm_generate_wrong_types(bad, square_model):
    assert check_outcome(square_model.generate, bad) is None
    for cond in ("start", "goal"):  # None is no condition: a path
        out = check_outcome(square_model.generate, [0.0, 1.0], **{cond: bad})
        assert (out is None) == (bad is not None)


@pytest.fixture(scope="module")
def square_model():
    t = np.linspace(0, 1, 30)
    X = np.column_stack([t, np.sin(3 * t)])
    train = [Demonstration.from_arrays(t, position=X + 0.01 * k) for k in range(3)]
    return KeypointHMM(epsilon=0.05, n_time_bins=10, n_jobs=1).fit(train)


def test_fuzz_start_on_huge_values_overflow():
    """Found by the fuzz suite: a start on a path of 1e300 values overflowed."""
    D = Demonstration.from_arrays
    train = [D([1.0, 2.0, 3.0], position=[[0.0], [1e300], [2e300]])] * 2
    model = KeypointHMM(epsilon=0.0, n_time_bins=1, levels=1, n_jobs=1)
    model.fit(train)
    path = model.generate(np.linspace(0, 1, 15), start={"position": [0.0]})
    assert np.isfinite(path.X).all()


@pytest.mark.parametrize("case", ["huge values", "tiny time steps"])
def test_fuzz_generated_velocity_overflow(case):
    """Found by the fuzz suite: deriving the generated velocity overflowed."""
    scale = 1e307 if case == "huge values" else 1.0
    t = np.arange(1.0, 6.0)
    X = scale * np.array([[1.0], [-1.0], [1.0], [-1.0], [1.0]])
    train = [Demonstration.from_arrays(t, position=X)] * 2
    model = KeypointHMM(epsilon=0.0, n_time_bins=5, n_jobs=1).fit(train)
    times = np.linspace(0, 1, 15) * (1e-3 if case == "huge values" else 1e-300)
    try:
        path = model.generate(times, dense=True)
    except ndlfd.NdlfdError:
        return  # the fix may refuse it: one error of ours
    assert np.isfinite(path.X).all()
