"""ndlfd plot of two hands: both drawn in space, each with its triads."""

import numpy as np
import pytest
from cli_helpers import cli, keep_figures

from hands_data import two_hands
from ndlfd.io import write_csv


def test_plot_draws_every_hand_in_space(tmp_path, capsys, monkeypatch):
    pytest.importorskip("matplotlib")
    figures = keep_figures(monkeypatch)
    demos, _ = two_hands(3, seed=1, n_samples=60)
    folder = tmp_path / "demos"
    folder.mkdir()
    for i, d in enumerate(demos):
        write_csv(d.with_frames(None), folder / f"demo{i}.csv")
    rc, err = cli(capsys, "plot", folder, "--triads", "4", "-o", tmp_path / "p.png")
    assert rc == 0, err
    line = err[-1]
    assert "in 3-D (left_position, right_position)" in line, line
    assert "orientation triads (left_orientation)" in line
    assert "orientation triads (right_orientation)" in line
    ax = figures[-1].axes[0]
    assert ax.name == "3d"
    # both hands' demonstrations are lines on the same axes, as written
    drawn = [np.column_stack(ln.get_data_3d()) for ln in ax.lines]
    for d in demos:
        for hand in ("left_position", "right_position"):
            P = d.get(hand)
            assert any(a.shape == P.shape and np.allclose(a, P) for a in drawn), hand
