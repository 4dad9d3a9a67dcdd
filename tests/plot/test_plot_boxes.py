"""ndlfd.plot's box plots (plot/_boxes.py)."""

import numpy as np
import pytest

pytest.importorskip("matplotlib")

from ndlfd import ValidationError
from ndlfd.plot import (
    plot_boxplot,
    plot_keypoint_counts,
)


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
