"""ndlfd.hmm file format: round trips, the committed v1 fixture, bad files."""

from __future__ import annotations

import sys
from pathlib import Path

import numpy as np
import pytest

from ndlfd._errors import ModelFormatError
from ndlfd.hmm import DiscreteHMM, estimate, viterbi

TESTS = Path(__file__).resolve().parents[1]
sys.path.insert(0, str(TESTS))
sys.path.insert(0, str(TESTS / "data"))

import make_hmm_v1  # noqa: E402
from hmm_cases import same_model  # noqa: E402

import reference_hmm as ref  # noqa: E402


@pytest.mark.parametrize("p", [None, 0.0, 0.3])
def test_save_load_round_trip(tmp_path, p):
    model = estimate(
        [[5, 1, 1, 9], [1, 9]], [[0, 1, 1, 2], [1, 2]], 10**9, 3,
        pseudo_transition=p, pseudo_emission=0.5,
    )  # fmt: skip
    f = tmp_path / "m.npz"
    model.save(f)
    back = DiscreteHMM.load(f)
    same_model(model, back)
    for obs in ([0, 1, 2], [2, 2], [1]):
        a, la = viterbi(model, obs)
        b, lb = viterbi(back, obs)
        np.testing.assert_array_equal(a, b)
        assert la == lb


def test_to_arrays_prefix_embeds_in_other_dicts():
    model = estimate([0, 1], [0, 1], 2, 2)
    arrays = {"other": np.zeros(3), **model.to_arrays(prefix="hmm/")}
    same_model(model, DiscreteHMM.from_arrays(arrays, prefix="hmm/"))
    with pytest.raises(ModelFormatError, match=r"missing array 'x/sizes'"):
        DiscreteHMM.from_arrays(arrays, prefix="x/")


def test_committed_v1_fixture_loads_and_decodes():
    model = DiscreteHMM.load(make_hmm_v1.FIXTURE)
    same_model(model, make_hmm_v1.build())
    path, logp = viterbi(model, make_hmm_v1.DECODE)
    np.testing.assert_array_equal(path, make_hmm_v1.EXPECTED_PATH)
    ref_path, ref_logp = ref.reference_viterbi(
        make_hmm_v1.STATES,
        make_hmm_v1.SYMBOLS,
        make_hmm_v1.N_STATES,
        make_hmm_v1.N_SYMBOLS,
        make_hmm_v1.DECODE,
        r=make_hmm_v1.PSEUDO_EMISSION,
    )
    np.testing.assert_array_equal(path, ref_path)
    assert logp == ref_logp


def test_foreign_and_broken_files(tmp_path):
    np.savez(tmp_path / "plain.npz", a=np.zeros(3))
    with pytest.raises(ModelFormatError, match="without ndlfd metadata"):
        DiscreteHMM.load(tmp_path / "plain.npz")
    (tmp_path / "noise.npz").write_bytes(np.random.default_rng(0).bytes(300))
    with pytest.raises(ModelFormatError, match="not readable"):
        DiscreteHMM.load(tmp_path / "noise.npz")
    good = make_hmm_v1.FIXTURE.read_bytes()
    (tmp_path / "trunc.npz").write_bytes(good[: len(good) // 2])
    with pytest.raises(ModelFormatError, match="not readable"):
        DiscreteHMM.load(tmp_path / "trunc.npz")
    with pytest.raises(ModelFormatError, match="no such file"):
        DiscreteHMM.load(tmp_path / "missing.npz")


def _tampered(tmp_path, key, value):
    with np.load(make_hmm_v1.FIXTURE, allow_pickle=False) as z:
        arrays = {k: z[k] for k in z.files}
    arrays[key] = value(arrays[key])
    f = tmp_path / f"tampered_{key}.npz"
    np.savez(f, **arrays)
    return f


@pytest.mark.parametrize(
    ("key", "change", "match"),
    [
        ("states", lambda a: a[::-1].copy(), "strictly increasing ids"),
        ("states", lambda a: a + 100, "strictly increasing ids in 0..11"),
        ("states", lambda a: a.astype(float), "integer array"),
        ("transition_counts", lambda a: a * 0, "must be >= 1"),
        ("transition_counts", lambda a: a + 1, "inconsistent"),
        ("transition_targets", lambda a: a + 50, r"must lie in 0..\d"),
        ("transition_indptr", lambda a: a[:-1], "must have shape"),
        ("emission_symbols", lambda a: a[::-1].copy(), "strictly increasing in each"),
        ("emission_counts", lambda a: a[:-1], "one per entry"),
        ("start_counts", lambda a: a * 2, "summing to n_sequences"),
        ("sizes", lambda a: a[:2], r"shape \(3,\)"),
        ("sizes", lambda a: np.array([0, a[1], a[2]]), "must be >= 1"),
        ("pseudo", lambda a: np.array([-1.0, a[1]]), "pseudo_transition must be"),
        ("pseudo", lambda a: np.array([a[0], np.inf]), "pseudo_emission must be"),
        ("pseudo", lambda a: a.reshape(1, 2), "1-D float array"),
    ],
)
def test_tampered_arrays_are_refused(tmp_path, key, change, match):
    f = _tampered(tmp_path, key, change)
    with pytest.raises(ModelFormatError, match=match):
        DiscreteHMM.load(f)
