"""ndlfd.plot's orientation triads (plot/_triads.py)."""

import itertools

import numpy as np
import pytest
from hypothesis import given, settings
from hypothesis import strategies as st

pytest.importorskip("matplotlib")

from ndlfd import ValidationError
from ndlfd.plot import (
    new_figure,
    plot_triads,
    save_figure,
    triad_indices,
)

PNG_MAGIC = b"\x89PNG\r\n\x1a\n"


def _matrix(q):
    """The rotation matrix of a quaternion (w, x, y, z), by the textbook formula."""
    w, x, y, z = q / np.linalg.norm(q)
    return np.array(
        [
            [1 - 2 * (y * y + z * z), 2 * (x * y - w * z), 2 * (x * z + w * y)],
            [2 * (x * y + w * z), 1 - 2 * (x * x + z * z), 2 * (y * z - w * x)],
            [2 * (x * z - w * y), 2 * (y * z + w * x), 1 - 2 * (x * x + y * y)],
        ]
    )


def _triads_drawn(ax):
    """(base, tip) of every drawn triad line, per axis x, y, z: 3 x (m, 2, 3)."""
    out = []
    for line in ax.lines[-3:]:
        xyz = np.column_stack(line.get_data_3d()).reshape(-1, 3, 3)
        assert np.all(np.isnan(xyz[:, 2]))  # the gaps between triads
        out.append(xyz[:, :2])
    return out


def _brute_triad_indices(P, k):
    """The first sample at or past each of k equal steps of arc length."""
    s = [0.0]
    for a, b in itertools.pairwise(P):
        s.append(s[-1] + float(np.sqrt(np.sum((b - a) ** 2))))
    if k == 1:
        return [0]
    if s[-1] <= 0:
        return sorted({round(j * (len(P) - 1) / (k - 1)) for j in range(k)})
    out = []
    for j in range(k):
        target = j * s[-1] / (k - 1) * (1 - 1e-12)
        out.append(next(i for i in range(len(P)) if s[i] >= target))
    return sorted(set(out))


@settings(max_examples=60, deadline=None, derandomize=True)
@given(
    steps=st.lists(
        st.tuples(*[st.sampled_from([0.0, 0.25, -0.5, 1.0, 2.0])] * 3),
        min_size=1,
        max_size=30,
    ),
    k=st.integers(1, 12),
)
def test_triad_indices_match_a_brute_force_walk(steps, k):
    """Steps from a small set (pauses, repeats): ties defined by the reference."""
    P = np.vstack([np.zeros(3), np.cumsum(np.array(steps), axis=0)])
    got = triad_indices(P, k)
    want = _brute_triad_indices(P, min(k, len(P)))
    assert got.tolist() == want
    assert got[0] == 0
    if k > 1 and np.any(np.diff(P, axis=0)):
        assert got[-1] == len(P) - 1


def test_triads_are_the_rotated_axes(tmp_path):
    rng = np.random.default_rng(7)
    n = 50
    s = np.linspace(0, 1, n)
    P = np.column_stack([s, np.sin(3 * s), 0.5 * s])
    Q = rng.normal(size=(n, 4))
    Q[::2] *= 3.0  # not unit: normalized
    _, (ax,) = new_figure(1, dims=3)
    idx = plot_triads(ax, P, Q, n_triads=6, length=0.2)
    assert idx.tolist() == triad_indices(P, 6).tolist()
    for a, segs in enumerate(_triads_drawn(ax)):
        np.testing.assert_array_equal(segs[:, 0], P[idx])
        for i, (base, tip) in zip(idx, segs, strict=True):
            np.testing.assert_allclose((tip - base) / 0.2, _matrix(Q[i])[:, a],
                                       atol=1e-12)  # fmt: skip
    # q and -q: the same rotation, the same triads
    _, (ax2,) = new_figure(1, dims=3)
    plot_triads(ax2, P, -Q, n_triads=6, length=0.2)
    for a, b in zip(_triads_drawn(ax), _triads_drawn(ax2), strict=True):
        np.testing.assert_allclose(a, b, atol=1e-12)
    # by hand: 90 degrees about x takes y to z and z to -y
    _, (ax3,) = new_figure(1, dims=3)
    c = np.sqrt(0.5)
    plot_triads(ax3, P[:2], [[c, c, 0, 0]] * 2, n_triads=1, length=1.0)
    (x,), (y,), (z,) = (d[:, 1] - d[:, 0] for d in _triads_drawn(ax3))
    np.testing.assert_allclose([x, y, z], [[1, 0, 0], [0, 0, 1], [0, -1, 0]],
                               atol=1e-15)  # fmt: skip
    save_figure(ax.figure, tmp_path / "t.png")
    assert (tmp_path / "t.png").read_bytes()[:8] == PNG_MAGIC


def test_triads_default_length_and_errors():
    P = np.column_stack([np.linspace(0, 2, 10), np.zeros(10), np.zeros(10)])
    Q = np.tile([1.0, 0, 0, 0], (10, 1))
    _, (ax,) = new_figure(1, dims=3)
    plot_triads(ax, P, Q, n_triads=3)
    x = _triads_drawn(ax)[0]
    np.testing.assert_allclose(x[:, 1] - x[:, 0], [[0.2, 0, 0]] * 3)  # 2 / 10
    for bad, match in [
        ((P[:, :2], Q), r"positions of shape \(n, 3\)"),
        ((P, Q[:5]), r"quaternions of shape \(n, 4\)"),
        ((P, 0 * Q), "non-zero norm"),
        ((np.where(P == 0, np.nan, P), Q), "finite"),
    ]:
        with pytest.raises(ValidationError, match=match):
            plot_triads(ax, *bad)
