"""ndlfd.plot's paths (plot/_paths.py): demonstrations, a path, samples, comparisons."""

import numpy as np
import pytest

pytest.importorskip("matplotlib")

from ndlfd import ValidationError
from ndlfd.demonstration import Demonstration
from ndlfd.plot import (
    GEN_COLOR,
    new_figure,
    plot_comparison,
    plot_demos,
    plot_keypoint_counts,
    plot_path,
    plot_samples,
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
