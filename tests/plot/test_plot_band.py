"""ndlfd.plot's band (plot/_band.py): its polygons and the patch drawn."""

import numpy as np
import pytest

pytest.importorskip("matplotlib")

from ndlfd import ValidationError
from ndlfd.plot import (
    new_figure,
    plot_band,
)


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
