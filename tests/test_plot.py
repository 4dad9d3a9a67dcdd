import itertools

import numpy as np
import pytest
from hypothesis import given, settings
from hypothesis import strategies as st

pytest.importorskip("matplotlib")

from ndlfd import ValidationError
from ndlfd.demonstration import Demonstration
from ndlfd.plot import (
    GEN_COLOR,
    new_figure,
    plot_band,
    plot_boxplot,
    plot_comparison,
    plot_demos,
    plot_keypoint_counts,
    plot_path,
    plot_samples,
    plot_triads,
    save_figure,
    triad_indices,
)

PNG_MAGIC = b"\x89PNG\r\n\x1a\n"


def _demo(dims, seed=0):
    rng = np.random.default_rng(seed)
    t = np.linspace(0, 1, 30)
    P = np.cumsum(rng.normal(size=(30, dims)), axis=0)
    return Demonstration.from_arrays(t, position=P)


@pytest.mark.parametrize("dims", [2, 3])
def test_plot_demos_draws_every_layer_and_saves_png(tmp_path, dims):
    demos = [_demo(dims, s) for s in range(3)]
    kp = [np.array([0, 10, 29])] * 3
    ax = plot_demos(demos, keypoints=kp, generated=demos[0], test=demos[1], title="x")
    labels = [t.get_text() for t in ax.get_legend().get_texts()]
    assert labels == ["demonstrations", "test", "generated"]
    # 3 demos x (line, key points, start, goal) + test (3) + generated (4)
    assert len(ax.lines) == 3 * 4 + 3 + 4
    assert (ax.name == "3d") == (dims == 3)
    out = save_figure(ax.figure, tmp_path / "f.png")
    assert (tmp_path / "f.png").read_bytes()[:8] == PNG_MAGIC
    assert out == tmp_path / "f.png"
    assert [p.name for p in tmp_path.iterdir()] == ["f.png"]


def test_plot_path_marks_start_and_goal():
    _fig, (ax,) = new_figure(1)
    V = np.array([[0.0, 0.0], [1.0, 2.0], [3.0, 1.0]])
    plot_path(ax, V, keypoints=[0, 2])
    start, goal = ax.lines[2], ax.lines[3]
    assert start.get_marker() == "x" and goal.get_marker() == "*"
    np.testing.assert_array_equal(start.get_xydata(), V[:1])
    np.testing.assert_array_equal(goal.get_xydata(), V[-1:])
    np.testing.assert_array_equal(ax.lines[1].get_xydata(), V[[0, 2]])


def test_plot_errors():
    _fig, (ax,) = new_figure(1)
    with pytest.raises(ValidationError, match="shape"):
        plot_path(ax, np.zeros((4, 1)))
    with pytest.raises(ValidationError, match="at least one path"):
        plot_demos([])
    with pytest.raises(ValidationError, match="at least one setting"):
        plot_keypoint_counts({})


def test_keypoint_boxplots_have_one_box_per_setting():
    ax = plot_keypoint_counts({"a": [1, 2, 3], "b": [4, 5], "c": [6]})
    assert [t.get_text() for t in ax.get_xticklabels()] == ["a", "b", "c"]
    assert ax.get_ylabel() == "key points per demonstration"


def test_boxplot_keeps_empty_and_nonfinite_labels_in_place():
    ax = plot_boxplot(
        {"ndlfd": [0.1, np.nan, 0.3], "mean": [], "dmp": [np.inf, 2.0]},
        ylabel="DTW / range",
        title="t",
        log=True,
    )
    assert [t.get_text() for t in ax.get_xticklabels()] == ["ndlfd", "mean", "dmp"]
    assert ax.get_ylabel() == "DTW / range" and ax.get_yscale() == "log"
    with pytest.raises(ValidationError, match="at least one label"):
        plot_boxplot({})


def test_band_is_the_union_of_ellipses_and_strips():
    _fig, (ax,) = new_figure(1)
    # a vertical path: the strip is as wide as the x standard deviation, the
    # ellipses at the ends reach k * std_y beyond them
    P = np.array([[0.0, 0.0], [0.0, 1.0], [0.0, 1.0], [0.0, 2.0]])
    S = np.array([[0.5, 0.25]] * 4)
    plot_band(ax, P, S, k=2.0, label="band")
    (patch,) = ax.patches
    assert patch.get_label() == "band"
    np.testing.assert_allclose(patch.get_path().get_extents().bounds, [-1, -0.5, 2, 3])
    # a piece at every point and along every segment, each counter-clockwise
    polys = patch.get_path().to_polygons()
    assert len(polys) == 4 + 3
    for poly in polys:
        x, y = poly[:, 0], poly[:, 1]
        assert np.sum(x * np.roll(y, -1) - np.roll(x, -1) * y) >= 0
    # the path that crosses itself is covered without holes: its centre is in
    loop = np.array([[0, 0], [2, 2], [2, 0], [0, 2]], dtype=float)
    plot_band(ax, loop, np.full((4, 2), 0.3))
    assert ax.patches[1].get_path().contains_point((1.0, 1.0))
    # a path that never moves still gets a band
    plot_band(ax, np.zeros((3, 2)), np.ones((3, 2)))
    assert ax.patches[2].get_path().contains_point((0.5, 0.5))
    with pytest.raises(ValidationError, match="2-D paths"):
        plot_band(ax, np.zeros((3, 3)), np.zeros((3, 3)))
    with pytest.raises(ValidationError, match="std must be finite"):
        plot_band(ax, P, -S)


def test_comparison_draws_demos_test_paths_and_bands(tmp_path):
    demos = [_demo(2, s) for s in range(3)]
    paths = {"mean": demos[0].get("position"), "ndlfd": demos[1].get("position")}
    stds = {"ndlfd": np.full((30, 2), 0.1), "mean": None}
    ax = plot_comparison(demos[1:], demos[0], paths, stds=stds, title="fold 0")
    labels = [t.get_text() for t in ax.get_legend().get_texts()]
    assert labels == ["training demos", "held out", "mean", "ndlfd ±1 sd", "ndlfd"]
    assert len(ax.patches) == 1
    ndlfd_line = next(ln for ln in ax.lines if ln.get_label() == "ndlfd")
    assert ndlfd_line.get_color() == GEN_COLOR
    save_figure(ax.figure, tmp_path / "c.png")
    assert (tmp_path / "c.png").read_bytes()[:8] == PNG_MAGIC


# ------------------------------------------------------- orientation triads
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


def test_plot_samples_draws_thin_lines_with_one_label():
    _, (ax,) = new_figure(1)
    s = np.linspace(0, 1, 15)
    paths = [np.column_stack([s, s**k, s]) for k in (1, 2, 3)]
    plot_samples(ax, paths)
    assert len(ax.lines) == 3
    for line, p in zip(ax.lines, paths, strict=True):
        np.testing.assert_array_equal(line.get_xydata(), p[:, :2])
        assert line.get_linewidth() < 1 and line.get_color() == GEN_COLOR
    labels = [ln.get_label() for ln in ax.lines]
    assert labels[0] == "samples" and all(lb.startswith("_") for lb in labels[1:])
    with pytest.raises(ValidationError, match="at least one path"):
        plot_samples(ax, [])
    with pytest.raises(ValidationError, match=r"shape \(n_samples, 2 or 3\)"):
        plot_samples(ax, [s])


def test_plot_demos_colours_each_route_and_labels_its_size():
    from ndlfd.plot import ROUTE_COLORS

    demos = [_demo(2, s) for s in range(5)]
    routes = [0, 1, 0, 2, 1]
    ax = plot_demos(demos, keypoints=[np.array([0, 29])] * 5, routes=routes)
    labels = [t.get_text() for t in ax.get_legend().get_texts()]
    assert labels == [
        "route 0 (2 demonstrations)",
        "route 1 (2 demonstrations)",
        "route 2 (1 demonstrations)",
    ]
    # every demonstration: line, key points, start, goal; line and dots in
    # the route's colour
    for i, r in enumerate(routes):
        line, dots = ax.lines[4 * i], ax.lines[4 * i + 1]
        assert line.get_color() == ROUTE_COLORS[r] == dots.get_color()
    # one route: the plain colour and label
    ax = plot_demos(demos, routes=[0] * 5)
    assert [t.get_text() for t in ax.get_legend().get_texts()] == ["demonstrations"]
    with pytest.raises(ValidationError, match="one route per demonstration"):
        plot_demos(demos, routes=[0, 1])


def _joints(seed, n=40):
    rng = np.random.default_rng(seed)
    t = np.linspace(0.0, 2.0 + 0.1 * seed, n)
    J = np.cumsum(rng.normal(size=(n, 3)), axis=0) * [1.0, 30.0, 0.01]
    g = (t > t[-1] / 2).astype(float)
    return Demonstration.from_arrays(t, joints=J, gripper=g)


def test_plot_channels_draws_each_channel_over_shared_time():
    from ndlfd.plot import ROUTE_COLORS, plot_channels

    demos = [_joints(s) for s in range(3)]
    kp = [np.array([0, 7, 39])] * 3
    gen = _joints(9)
    std = np.abs(np.random.default_rng(1).normal(size=gen.X.shape)) + 0.1
    order = ["joints1", "gripper0", "joints0"]
    fig, axes = plot_channels(demos, columns=order, keypoints=kp, generated=gen,
                              std=std, title="arm")  # fmt: skip
    assert len(axes) == 3 and fig._suptitle.get_text() == "arm"
    assert [ax.get_ylabel() for ax in axes] == order
    assert axes[-1].get_xlabel() == "time"
    for ax in axes[1:]:  # one time axis
        assert axes[0].get_shared_x_axes().joined(axes[0], ax)
    for ax, c in zip(axes, order, strict=True):
        # each channel on its own scale (not an equal aspect: no sliver)
        assert ax.get_aspect() == "auto" and ax.name != "3d"
        j = demos[0].columns.index(c)
        for i, d in enumerate(demos):
            line, dots = ax.lines[2 * i], ax.lines[2 * i + 1]
            np.testing.assert_array_equal(line.get_xydata(), np.c_[d.t, d.X[:, j]])
            np.testing.assert_array_equal(
                dots.get_xydata(), np.c_[d.t[kp[i]], d.X[kp[i], j]]
            )
        g = ax.lines[-1]
        np.testing.assert_array_equal(g.get_xydata(), np.c_[gen.t, gen.X[:, j]])
        # the band: +-1 sd around the generated channel, no wider
        (band,) = ax.collections
        mid, s = gen.X[20, j], std[20, j]
        inside = (gen.t[20], mid + 0.9 * s)
        outside = (gen.t[20], mid + 1.1 * s)
        path = band.get_paths()[0]
        assert path.contains_point(inside) and not path.contains_point(outside)
    labels = [t.get_text() for t in axes[0].get_legend().get_texts()]
    assert labels == ["demonstrations", "generated ±1 sd", "generated"]
    # routes colour the demonstrations
    _, axes = plot_channels(demos, routes=[0, 1, 0])
    assert [ln.get_color() for ln in axes[0].lines] == [
        ROUTE_COLORS[0], ROUTE_COLORS[1], ROUTE_COLORS[0]
    ]  # fmt: skip
    with pytest.raises(ValidationError, match=r"columns must name columns .* got"):
        plot_channels(demos, columns=["elbow"])
    with pytest.raises(ValidationError, match="one route per demonstration"):
        plot_channels(demos, routes=[0])
    with pytest.raises(ValidationError, match="at least one demonstration"):
        plot_channels([])
