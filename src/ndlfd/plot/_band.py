"""A path's standard-deviation band: its polygons, and the band drawn.

:func:`band_polygons` is plain numpy: the polygons whose union is the band,
each turned counter-clockwise so that, filled as one path with the non-zero
rule, their overlaps neither darken nor leave holes. :func:`plot_band` draws
them as one patch (matplotlib imported when it is called).
"""

from __future__ import annotations

import numpy as np

from .._errors import ValidationError
from ._figures import GEN_COLOR

__all__ = ["band_polygons", "plot_band"]


def _ccw(poly: np.ndarray) -> np.ndarray:
    """``poly`` (..., m, 2) with every polygon turned counter-clockwise."""
    x, y = poly[..., 0], poly[..., 1]
    area = np.sum(x * np.roll(y, -1, axis=-1) - np.roll(x, -1, axis=-1) * y, axis=-1)
    return np.where((area < 0)[..., None, None], poly[..., ::-1, :], poly)


def band_polygons(values, std, k: float = 1.0) -> list[np.ndarray]:
    """The polygons whose union is the band of ``k`` standard deviations.

    At every point the ellipse with semi-axes ``k * std`` (a 16-gon), and
    along every segment the strip reaching on both sides along the segment's
    normal ``n`` to ``k * sqrt((n_x s_x)^2 + (n_y s_y)^2)``.

    Parameters
    ----------
    values : array-like of shape (n_samples, 2)
        The path.
    std : array-like of shape (n_samples, 2)
        Standard deviation of each coordinate at each point, finite, >= 0.
    k : float, default=1.0
        Half-width of the band in standard deviations.

    Returns
    -------
    pieces : list of ndarray of shape (n_polygons, n_corners, 2)
        The ellipses (16 corners), then the strips (4 corners) when the path
        has more than one point; every polygon counter-clockwise.

    Examples
    --------
    >>> ellipses, strips = band_polygons([[0, 0], [2, 0]], [[0, 1], [0, 1]])
    >>> ellipses.shape, strips.shape, strips[0].round(6).tolist()
    ((2, 16, 2), (1, 4, 2), [[0.0, -1.0], [2.0, -1.0], [2.0, 1.0], [0.0, 1.0]])
    """
    P = np.asarray(values, dtype=float)
    S = np.asarray(std, dtype=float)
    if P.ndim != 2 or P.shape[1] != 2:
        raise ValidationError(
            f"plot_band draws 2-D paths of shape (n_samples, 2); got {P.shape}"
        )
    if S.shape != P.shape or not np.isfinite(S).all() or (S < 0).any():
        raise ValidationError(
            f"std must be finite, >= 0 and of the path's shape {P.shape}; got an"
            f" array of shape {S.shape}"
        )
    phi = np.linspace(0.0, 2.0 * np.pi, 16, endpoint=False)
    circle = np.column_stack([np.cos(phi), np.sin(phi)])
    pieces = [P[:, None, :] + k * S[:, None, :] * circle[None, :, :]]
    if P.shape[0] > 1:
        seg = np.diff(P, axis=0)
        length = np.linalg.norm(seg, axis=1, keepdims=True)
        N = np.column_stack([-seg[:, 1], seg[:, 0]]) / np.where(length > 0, length, 1)
        w0 = k * np.linalg.norm(N * S[:-1], axis=1, keepdims=True)
        w1 = k * np.linalg.norm(N * S[1:], axis=1, keepdims=True)
        quads = np.stack(
            [P[:-1] + w0 * N, P[1:] + w1 * N, P[1:] - w1 * N, P[:-1] - w0 * N], axis=1
        )
        pieces.append(quads)
    return [_ccw(poly) for poly in pieces]


def plot_band(
    ax, values, std, *, k: float = 1.0, color=GEN_COLOR, alpha=0.2, label=None
):
    """Shade a band of ``k`` standard deviations around a 2-D path.

    The band is the union of, at every point, the ellipse with semi-axes
    ``k * std`` (independent coordinates) and, along every segment, the strip
    reaching on both sides along the segment's normal ``n`` to the standard
    deviation in that direction, ``k * sqrt((n_x s_x)^2 + (n_y s_y)^2)``
    (:func:`band_polygons`). It is drawn as one patch, so
    overlapping pieces do not darken each other and a path that crosses
    itself leaves no holes.

    Parameters
    ----------
    ax : Axes
        Target (2-D) axes.
    values : array-like of shape (n_samples, 2)
        The path.
    std : array-like of shape (n_samples, 2)
        Standard deviation of each coordinate at each point.
    k : float, default=1.0
        Half-width of the band in standard deviations.
    color : str
        Fill colour.
    alpha : float, default=0.2
        Fill opacity.
    label : str, optional
        Legend label.

    Returns
    -------
    ax : Axes

    Examples
    --------
    >>> from ndlfd.plot import new_figure
    >>> _, (ax,) = new_figure(1)
    >>> ax = plot_band(ax, [[0, 0], [1, 0], [2, 0]], [[0, 1], [0, 1], [0, 2]])
    >>> [float(v) for v in ax.patches[0].get_path().get_extents().bounds]
    [0.0, -2.0, 2.0, 4.0]
    """
    from matplotlib.patches import PathPatch
    from matplotlib.path import Path as MplPath

    pieces = band_polygons(values, std, k)
    verts, codes = [], []
    for poly in pieces:
        m = poly.shape[1]
        code = np.full(m + 1, MplPath.LINETO, dtype=MplPath.code_type)
        code[0], code[-1] = MplPath.MOVETO, MplPath.CLOSEPOLY
        verts.append(np.concatenate([poly, poly[:, :1]], axis=1).reshape(-1, 2))
        codes.append(np.tile(code, poly.shape[0]))
    patch = PathPatch(
        MplPath(np.concatenate(verts), np.concatenate(codes)),
        facecolor=color,
        edgecolor="none",
        alpha=alpha,
        label=label,
    )
    ax.add_patch(patch)
    ax.update_datalim(patch.get_path().vertices)
    ax.autoscale_view()
    return ax
