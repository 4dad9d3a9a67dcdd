import numpy as np
import pytest

pytest.importorskip("matplotlib")

from ndlfd import ValidationError
from ndlfd.demo import Demonstration
from ndlfd.plot import (
    new_figure,
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
