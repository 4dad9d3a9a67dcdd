"""The resource bounds: each is refused with one error stating the bound.

The sizes are real (no bound is patched), and each refusal comes before the
large array is allocated: the traced peak of the refused call stays small.
"""

import tracemalloc

import numpy as np
import pytest

import ndlfd
from ndlfd import KeypointHMM, ResourceLimitError, TimeBins, hmm
from ndlfd._validation import MAX_TIME_BINS, MAX_VALUES, MAX_WORK_BYTES


def _refused(fn, *args, **kwargs):
    """The message of the ResourceLimitError of a call, and its traced peak."""
    tracemalloc.start()
    try:
        with pytest.raises(ResourceLimitError) as info:
            fn(*args, **kwargs)
        peak = tracemalloc.get_traced_memory()[1]
    finally:
        tracemalloc.stop()
    assert peak < 64 * 2**20, f"{peak / 2**20:.0f} MiB allocated before the refusal"
    return str(info.value)


@pytest.fixture(scope="module")
def wide_model():
    """2**14 seen states in one chain and one unseen; all emit symbol 0, r > 0."""
    n = 2**14
    states = np.arange(n)
    return hmm.estimate(states, np.zeros(n, int), n + 1, 2, pseudo_emission=1.0)


def test_viterbi_back_pointers_are_bounded(wide_model):
    # r > 0: every seen state and the unseen class are candidates at every
    # step, 4 bytes each: (2**14 + 1) * 4 * T > 2 GiB from T = 32,767 on
    n_seen = wide_model.states_.size
    T = MAX_WORK_BYTES // (4 * (n_seen + 1)) + 1
    msg = _refused(hmm.viterbi, wide_model, np.zeros(T, int))
    assert f"Viterbi back-pointers for {T:,} steps over {n_seen:,} seen" in msg
    assert "above the bound of 2,048 MiB" in msg
    path, logp = hmm.viterbi(wide_model, np.zeros(3, int))  # small: decoded
    assert path.shape == (3,) and np.isfinite(logp)


@pytest.mark.parametrize("fn", ["posterior", "sample_paths"])
def test_forward_pass_is_bounded(wide_model, fn):
    n_seen = wide_model.states_.size
    T = MAX_WORK_BYTES // (8 * (n_seen + 1)) + 1
    msg = _refused(getattr(hmm, fn), wide_model, np.zeros(T, int))
    assert f"the forward pass of {T:,} steps over {n_seen:,} seen states" in msg


def test_sampled_paths_are_bounded(wide_model):
    n = MAX_WORK_BYTES // 8 + 1  # one step each: n int64 ids
    msg = _refused(hmm.sample_paths, wide_model, [0], n, random_state=0)
    assert f"{n:,} sampled paths of 1 steps" in msg


def test_time_bins_are_bounded():
    for call in (
        lambda: TimeBins(MAX_TIME_BINS + 1),
        lambda: KeypointHMM(n_time_bins=MAX_TIME_BINS + 1).fit(["never read"]),
    ):
        assert f"at most {MAX_TIME_BINS:,}" in _refused(call)
        assert f"got {MAX_TIME_BINS + 1:,}" in _refused(call)
    assert TimeBins(MAX_TIME_BINS).n_bins == MAX_TIME_BINS  # the bound itself is in


def test_hmm_memory_does_not_follow_n_symbols():
    """An HMM over 2**62 symbols decodes in memory of the symbols emitted."""
    nt = 2**62
    obs = [0, 2**61, nt - 1]
    model = hmm.estimate([[0, 1, 2]], [obs], 3, nt, pseudo_emission=0.5)
    tracemalloc.start()
    try:
        path, _ = hmm.viterbi(model, obs)
        post = hmm.posterior(model, [*obs, 12345])  # 12345: never emitted
        peak = tracemalloc.get_traced_memory()[1]
    finally:
        tracemalloc.stop()
    assert peak < 2**20
    assert path.tolist() == [0, 1, 2]
    assert post.probabilities.shape == (4, 3)


def test_points_and_samples_are_bounded():
    # zero-stride views: the inputs cost nothing, their float64 copies 2 GiB
    points = np.broadcast_to(np.float32(0), (MAX_VALUES // 2 + 1, 2))
    msg = _refused(ndlfd.simplify, points, 0.1)
    assert f"points must hold at most {MAX_VALUES:,} values" in msg
    assert f"got {points.size:,} values, shape {points.shape}" in msg
    t = np.broadcast_to(np.float32(0), (MAX_VALUES + 1,))
    msg = _refused(ndlfd.Demonstration.from_arrays, t, position=[[0.0]])
    assert f"at most {MAX_VALUES:,} values" in msg


def test_state_ids_beyond_int64_are_refused_but_not_n_states():
    # n_states is the pseudo-count's m, of any size (interned cells of many
    # columns); the ids themselves are int64
    model = hmm.estimate([0, 5], [0, 0], 2**70, 1)
    assert model.n_states == 2**70 and model.states_.tolist() == [0, 5]
    with pytest.raises(ndlfd.ValidationError, match="states"):
        hmm.estimate([2**63], [0], 2**70, 1)
    with pytest.raises(ndlfd.ValidationError, match="int64"):
        ndlfd.Codebook([2**32, 2**32]).encode([[0.5, 0.5]])
    with pytest.raises(ndlfd.ValidationError, match="int64"):
        model.transition_matrix()
