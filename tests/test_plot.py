import numpy as np
import pytest

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
    save_figure,
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
