"""ndlfd.plot's channels over time (plot/_channels.py)."""

import numpy as np
import pytest

pytest.importorskip("matplotlib")

from ndlfd import ValidationError
from ndlfd.demonstration import Demonstration


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
