"""Fit statistics: exact sums, exact merges and the template choice."""

from collections import Counter
from fractions import Fraction

import numpy as np
import pytest
from hypothesis import given, settings
from hypothesis import strategies as st

from ndlfd import Codebook, ModelFormatError, ValidationError, hmm
from ndlfd.learner import FitStats, RangeStats
from ndlfd.learner._exact import from_limbs, scale_exponents, to_limbs
from ndlfd.learner._templates import template_keys, template_mask

# -- exact sums --------------------------------------------------------------------

finite = st.floats(-1.0, 1.0, allow_nan=False, allow_subnormal=True)


@settings(max_examples=60, deadline=None)
@given(
    st.lists(finite, min_size=1, max_size=40),
    st.integers(-3, 3),
    st.randoms(use_true_random=False),
)
def test_limb_sums_are_exact_whatever_the_order(values, shift, rnd):
    scale = 2.0**shift
    u = np.array(values)[:, None] * scale
    E = scale_exponents(np.abs(u).max(axis=0))
    assert np.all(np.abs(u) <= np.ldexp(1.0, E))
    L = to_limbs(u, E)
    assert np.all(np.abs(L) <= 2**31)
    total = L.sum(axis=1)
    # any order and grouping of the integer sums gives the same limbs
    perm = list(range(len(values)))
    rnd.shuffle(perm)
    cut = rnd.randint(0, len(values))
    a = L[:, perm[:cut]].sum(axis=1)
    b = L[:, perm[cut:]].sum(axis=1)
    np.testing.assert_array_equal(a + b, total)
    # and the value is the exact sum up to rounding and the dropped remainders
    exact = sum(Fraction(float(x)) for x in u[:, 0])
    got = Fraction(float(from_limbs(total, E)[0]))
    bound = Fraction(2.0**-52) * sum(abs(Fraction(float(x))) for x in u[:, 0])
    bound += len(values) * Fraction(np.ldexp(1.0, int(E[0]) - 93))
    assert abs(got - exact) <= bound


def test_limbs_hand_worked():
    # E = 0: q = 2**-31, 2**-62, 2**-93; 0.75 = 1610612736 q1; -2**-40 = -2**22 q2
    L = to_limbs(np.array([[0.75], [-(2.0**-40)]]), np.array([0]))
    np.testing.assert_array_equal(L[:, :, 0], [[1610612736, 0], [0, -(2**22)], [0, 0]])
    assert from_limbs(L.sum(axis=1), [0])[0] == 0.75 - 2.0**-40
    np.testing.assert_array_equal(scale_exponents([0.5, 0.51, 1.0, 2.0**-1000]),
                                  [0, 0, 1, -900])  # fmt: skip


# -- FitStats ----------------------------------------------------------------------


def _cells(states, d):
    """State numbers 0..5 as cells of ``d`` columns (mixed radix, so ordered alike)."""
    return Codebook((1,) * (d - 2) + (2, 3)).to_levels(states)


def _demo_stats(j, rng, d=2, n_states=6, template=True):
    """Statistics of one random demonstration (and its raw pieces)."""
    n = int(rng.integers(2, 12))
    U = rng.uniform(-0.1, 1.1, (n, d))
    tau = np.linspace(0.0, 1.0, n)
    k = int(rng.integers(1, n + 1))
    idx = np.unique(np.r_[0, np.sort(rng.choice(n, k, replace=False))])
    states = rng.integers(0, n_states, idx.size)
    bins = np.sort(rng.integers(0, 5, idx.size))
    E = scale_exponents(np.full(d, 1.1))
    s = FitStats.of_demo(j, U, tau, idx, _cells(states, d), bins, exponents=E,
                         n_clipped=int(j % 3), template=template)  # fmt: skip
    return s, (U, tau, idx, states, bins)


@pytest.fixture(scope="module")
def per_demo():
    rng = np.random.default_rng(5)
    return [_demo_stats(j, rng, template=j % 2 == 0) for j in range(9)]


@settings(max_examples=40, deadline=None)
@given(st.data())
def test_merge_over_any_partition_and_tree_equals_all_at_once(per_demo, data):
    stats = [s for s, _ in per_demo]
    everything = stats[0].merge(*stats[1:])
    # a random partition into parts, each merged in a random order ...
    labels = data.draw(st.lists(st.integers(0, 3), min_size=9, max_size=9))
    parts = []
    for lab in sorted(set(labels)):
        members = [s for s, g in zip(stats, labels, strict=True) if g == lab]
        members = data.draw(st.permutations(members))
        parts.append(members[0].merge(*members[1:]))
    # ... and the parts merged pairwise in a random tree
    while len(parts) > 1:
        i = data.draw(st.integers(0, len(parts) - 2))
        a, b = parts.pop(i), parts.pop(i)
        parts.insert(i, b + a if data.draw(st.booleans()) else a + b)
    assert parts[0] == everything


def test_merged_statistics_against_plain_references(per_demo):
    stats = [s for s, _ in per_demo]
    raw = [r for _, r in per_demo]
    m = stats[4].merge(*stats[:4], *stats[5:])  # not in index order
    np.testing.assert_array_equal(m.demo_index, np.arange(9))
    kp, ks, kb = m.keypoint_lists()
    seen = np.unique(np.concatenate([r[3] for r in raw]))
    np.testing.assert_array_equal(m.centroid_cells, _cells(seen, 2))
    for j, (U, _tau, idx, states, bins) in enumerate(raw):
        np.testing.assert_array_equal(kp[j], idx)
        # interned: each state's rank among the seen ones, its cell kept
        np.testing.assert_array_equal(ks[j], np.searchsorted(seen, states))
        np.testing.assert_array_equal(m.centroid_cells[ks[j]], _cells(states, 2))
        np.testing.assert_array_equal(kb[j], bins)
        np.testing.assert_array_equal(m.first[j], U[0])
        np.testing.assert_array_equal(m.last[j], U[-1])
    # templates: the even demonstrations, whole, in order
    np.testing.assert_array_equal(m.template_index, [0, 2, 4, 6, 8])
    values, taus = m.templates()
    for v, t, j in zip(values, taus, m.template_index, strict=True):
        np.testing.assert_array_equal(v, raw[j][0])
        np.testing.assert_array_equal(t, raw[j][1])
    # held per template, read as one flat array each (and back from the flat)
    flat_values = np.concatenate([raw[j][0] for j in m.template_index])
    assert m.template_values.tobytes() == flat_values.tobytes()
    flat_tau = np.concatenate([raw[j][1] for j in m.template_index])
    assert m.template_tau.tobytes() == flat_tau.tobytes()
    back = FitStats.from_arrays(m.to_arrays())
    for a, b in zip(back.templates(), m.templates(), strict=True):
        assert [x.tobytes() for x in a] == [x.tobytes() for x in b]
    # centroids: the mean of the key-point values in each state (exact sums)
    groups: dict = {}
    for U, _, idx, states, _ in raw:
        for row, s in zip(U[idx], states, strict=True):
            groups.setdefault(int(s), []).append(row)
    ids, C = m.centroids()
    assert ids.tolist() == list(range(len(groups)))
    assert m.centroid_counts.tolist() == [len(groups[s]) for s in sorted(groups)]
    for s, c in zip(sorted(groups), C, strict=True):
        exact = [sum(Fraction(float(r[k])) for r in groups[s]) for k in range(2)]
        ref = [float(x / len(groups[s])) for x in exact]
        np.testing.assert_allclose(c, ref, rtol=4e-16, atol=1e-300)
    assert m.n_clipped == sum(j % 3 for j in range(9))
    # the HMM of the merged sequences is hmm.merge of the parts' HMMs
    a = stats[0].merge(*stats[1:5])
    b = stats[5].merge(*stats[6:])
    # (each part numbers its own cells: its ids are put in the merged numbering)
    where = {tuple(c): i for i, c in enumerate(m.centroid_cells.tolist())}

    def merged_ids(x):
        ids = np.array([where[tuple(c)] for c in x.centroid_cells.tolist()])
        return [ids[k] for k in x.keypoint_lists()[1]]

    est = [hmm.estimate(merged_ids(x), list(x.keypoint_lists()[2]), 6, 5)
           for x in (a, b, m)]  # fmt: skip
    merged = hmm.merge(est[:2])
    for k, v in est[2].to_arrays().items():
        np.testing.assert_array_equal(merged.to_arrays()[k], v, err_msg=k)


def test_merge_refuses_double_counting_and_other_fits(per_demo):
    s0, s1 = per_demo[0][0], per_demo[1][0]
    with pytest.raises(ValidationError, match="both hold demonstration 0"):
        s0.merge(s1, s0)
    rng = np.random.default_rng(0)
    other, _ = _demo_stats(5, rng, d=3)
    with pytest.raises(ValidationError, match="different fits"):
        s0 + other
    with pytest.raises(ValidationError, match="only merge FitStats"):
        s0.merge(RangeStats.of(0, np.zeros((2, 2))))


def test_arrays_round_trip_and_tampering(per_demo):
    m = per_demo[0][0].merge(*[s for s, _ in per_demo[1:]])
    arrays = m.to_arrays(prefix="stats_")
    assert all(a.dtype != object for a in arrays.values())
    assert FitStats.from_arrays(arrays, prefix="stats_") == m
    bad = dict(arrays, stats_keypoints=arrays["stats_keypoints"][:-1])
    with pytest.raises(ModelFormatError, match="keypoints has shape"):
        FitStats.from_arrays(bad, prefix="stats_")
    bad = dict(arrays, stats_centroid_counts=arrays["stats_centroid_counts"] + 1)
    with pytest.raises(ModelFormatError, match="do not add up"):
        FitStats.from_arrays(bad, prefix="stats_")
    bad = dict(arrays, stats_keypoints=arrays["stats_keypoints"] + 100)
    with pytest.raises(ModelFormatError, match="out of range"):
        FitStats.from_arrays(bad, prefix="stats_")
    bad = dict(arrays)
    del bad["stats_first"]
    with pytest.raises(ModelFormatError, match="stats_first"):
        FitStats.from_arrays(bad, prefix="stats_")
    bad = dict(arrays, stats_first=arrays["stats_first"].astype(str))
    with pytest.raises(ModelFormatError, match="dtype"):
        FitStats.from_arrays(bad, prefix="stats_")


def test_range_stats_against_numpy():
    rng = np.random.default_rng(1)
    arrays = [rng.normal(size=(int(rng.integers(1, 9)), 3)) for _ in range(7)]
    parts = [RangeStats.of(0, *arrays[:2])] + [
        RangeStats.of(i, a) for i, a in enumerate(arrays[2:], start=1)
    ]
    r = parts[3].merge(*parts[:3], *parts[4:])
    allX = np.vstack(arrays)
    np.testing.assert_array_equal(r.data_min, allX.min(axis=0))
    np.testing.assert_array_equal(r.data_max, allX.max(axis=0))
    assert r.n_samples == allX.shape[0] and r.n_demos == 7
    np.testing.assert_array_equal(r.items, np.arange(6))
    np.testing.assert_array_equal(r.demos_per_item, [2, 1, 1, 1, 1, 1])


@settings(max_examples=40, deadline=None)
@given(
    st.lists(st.integers(1, 6), min_size=1, max_size=12),
    st.randoms(use_true_random=False),
)
def test_shortest_and_longest_whatever_the_merge_order(lengths, rnd):
    # reference: the first item (by index) of the fewest / most samples
    # and the notes: distinct texts by first item, with their counts
    notes = [[f"kind {n % 3}"] for n in lengths]
    parts = [
        RangeStats.of(i, np.zeros((n, 1)), notes=notes[i])
        for i, n in enumerate(lengths)
    ]
    rnd.shuffle(parts)
    k = rnd.randrange(len(parts))
    r = parts[k].merge(*parts[:k], *parts[k + 1 :])
    assert r.min_samples == min(lengths) and r.max_samples == max(lengths)
    assert r.shortest_item == lengths.index(min(lengths))
    assert r.longest_item == lengths.index(max(lengths))
    flat = [n[0] for n in notes]
    want = [(t, flat.index(t), flat.count(t)) for t in dict.fromkeys(flat)]
    assert list(r.notes) == want


def _same_ranges(a: RangeStats, b: RangeStats) -> None:
    for k in ("data_min", "data_max", "items", "demos_per_item"):
        assert getattr(a, k).tobytes() == getattr(b, k).tobytes(), k
    for k in ("n_samples", "min_samples", "max_samples", "shortest_item",
              "longest_item", "notes", "repairs"):  # fmt: skip
        assert getattr(a, k) == getattr(b, k), k


@settings(max_examples=40, deadline=None)
@given(st.integers(0, 2**32 - 1), st.integers(1, 10), st.booleans())
def test_of_items_is_the_merge_of_each_items_of(seed, n_items, zeros):
    # a chunk of items read at once (pass 1) against one RangeStats each,
    # merged: files of several demonstrations, notes, repairs, signed zeros
    rng = np.random.default_rng(seed)
    entries = []
    for i in sorted(rng.choice(40, n_items, replace=False).tolist()):
        arrays = []
        for _ in range(int(rng.integers(1, 4))):
            a = rng.normal(size=(int(rng.integers(1, 20)), 3))
            if zeros:
                a[rng.random(a.shape) < 0.3] = rng.choice([0.0, -0.0])
            arrays.append(a)
        notes = [f"note {int(rng.integers(0, 3))}" for _ in arrays]
        repairs = (("jitter", i, f"file{i}", 1),) if rng.random() < 0.5 else ()
        entries.append((i, arrays, notes, repairs))
    parts = [RangeStats.of(i, *a, notes=n, repairs=r) for i, a, n, r in entries]
    _same_ranges(RangeStats.of_items(entries), parts[0].merge(*parts[1:]))


# -- templates ---------------------------------------------------------------------


def _splitmix64_reference(x: int) -> int:
    """splitmix64's output function with plain Python integers (mod 2**64)."""
    mask = 2**64 - 1
    z = x & mask
    z = ((z ^ (z >> 30)) * 0xBF58476D1CE4E5B9) & mask
    z = ((z ^ (z >> 27)) * 0x94D049BB133111EB) & mask
    return z ^ (z >> 31)


def test_template_keys_and_choice_against_a_plain_reference():
    word = 123456789123456789
    keys = template_keys(word, np.arange(50))
    ref = [
        _splitmix64_reference(word + (i + 1) * 0x9E3779B97F4A7C15) for i in range(50)
    ]
    assert [int(k) for k in keys] == ref
    # the first value of splitmix64 seeded with 0 (Vigna's reference output)
    assert int(template_keys(0, [0])[0]) == 0xE220A8397B1DCDAF
    mask = template_mask(50, 7, 3)
    words = np.random.SeedSequence(3).generate_state(1, np.uint64)
    ref = [_splitmix64_reference(int(words[0]) + (i + 1) * 0x9E3779B97F4A7C15)
           for i in range(50)]  # fmt: skip
    assert np.flatnonzero(mask).tolist() == sorted(np.argsort(ref)[:7].tolist())
    np.testing.assert_array_equal(template_mask(50, 7, 3), mask)  # reproducible
    assert not np.array_equal(template_mask(50, 7, 4), mask)
    assert template_mask(7, 7, None).all() and template_mask(9, None, 0).all()
    # fresh entropy for None, one draw of a Generator
    assert template_mask(50, 7, None).sum() == 7
    g1, g2 = np.random.default_rng(8), np.random.default_rng(8)
    np.testing.assert_array_equal(template_mask(50, 7, g1), template_mask(50, 7, g2))
    r1, r2 = np.random.RandomState(8), np.random.RandomState(8)
    np.testing.assert_array_equal(template_mask(50, 7, r1), template_mask(50, 7, r2))
    with pytest.raises(ValidationError, match="random_state"):
        template_mask(50, 7, "seed")
    with pytest.raises(ValidationError, match=">= 0"):
        template_mask(50, 7, -1)


def test_template_choice_spreads_over_the_indices():
    # 2,000 demonstrations, 200 templates: about 20 in each tenth of the indices
    chosen = np.flatnonzero(template_mask(2000, 200, 0))
    per_tenth = np.bincount(chosen // 200, minlength=10)
    assert per_tenth.min() >= 8 and per_tenth.max() <= 35


def test_counter_reference_of_key_states(per_demo):
    # centroid counts are plain counts of the key states
    m = per_demo[0][0].merge(*[s for s, _ in per_demo[1:]])
    c = Counter(int(s) for _, r in per_demo for s in r[3])
    assert dict(zip(sorted(c), m.centroid_counts.tolist(), strict=True)) == c


@settings(max_examples=25, deadline=None)
@given(st.integers(0, 2**32 - 1), st.integers(1, 8))
def test_of_demos_is_the_merge_of_of_demo(seed, n_demos):
    # a chunk's statistics at once == the merge of one object per demonstration
    from ndlfd.learner._stats import DemoStats

    rng = np.random.default_rng(seed)
    parts = []
    for j in range(n_demos):
        n = int(rng.integers(1, 30))
        U = rng.uniform(-0.1, 1.1, (n, 3))
        tau = np.linspace(0.0, 1.0, n)
        keys = np.unique(np.concatenate([[0, n - 1], rng.integers(0, n, 4)]))
        states = rng.integers(0, 6, keys.size)  # repeated states across demos
        bins = rng.integers(0, 5, keys.size)
        clipped, template = int(rng.integers(0, 3)), bool(rng.random() < 0.5)
        parts.append(
            DemoStats(
                3 * j + 1, U, tau, keys, _cells(states, 3), bins, clipped, template
            )
        )
    E = scale_exponents(np.full(3, 1.1))
    one_by_one = [
        FitStats.of_demo(
            *p[:6], exponents=E, n_clipped=p.n_clipped, template=p.template
        )
        for p in parts
    ]
    want = one_by_one[0].merge(*one_by_one[1:])
    assert FitStats.of_demos(parts, exponents=E) == want
    assert FitStats.of_demos(parts[::-1], exponents=E) == want
