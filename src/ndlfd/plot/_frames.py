"""Task frames drawn on a position's axes (:func:`ndlfd.plot.plot_frames`).

Each frame is a marker at its position, one marker style per frame name, and
a frame with an orientation (7 values: x, y, z, then a unit quaternion w, x,
y, z) also a short arrow along its x axis, projected to the plotted plane on
2-D axes. Drawn on given axes; nothing here imports matplotlib.
"""

from __future__ import annotations

from collections.abc import Mapping, Sequence

import numpy as np

from .._errors import ValidationError

__all__ = ["FRAME_MARKERS", "frame_marker", "plot_frames"]

#: Marker styles of the task frames, one per frame name in order (none is a
#: key point's dot, a start's ``×`` or a goal's ``*``).
FRAME_MARKERS = ("s", "^", "D", "v", "P", "h", "<", ">", "p")


def frame_marker(name: str, names: Sequence[str]) -> str:
    """The marker style of frame ``name`` among ``names`` (in their order).

    Examples
    --------
    >>> frame_marker("place", ["object", "place"])
    '^'
    """
    return FRAME_MARKERS[list(names).index(name) % len(FRAME_MARKERS)]


def _extent(ax) -> float:
    """The largest extent of what ``ax`` shows (1 for an empty view)."""
    lims = [ax.get_xlim(), ax.get_ylim()]
    if ax.name == "3d":
        lims.append(ax.get_zlim())
    extent = max(abs(hi - lo) for lo, hi in lims)
    return float(extent) if np.isfinite(extent) and extent > 0 else 1.0


def _x_axes(quaternions: np.ndarray) -> np.ndarray:
    """The x axis (first column of the rotation matrix) of each (w, x, y, z)."""
    q = quaternions / np.linalg.norm(quaternions, axis=1, keepdims=True)
    w, x, y, z = q.T
    return np.column_stack(
        [1 - 2 * (y * y + z * z), 2 * (x * y + w * z), 2 * (x * z - w * y)]
    )


def plot_frames(
    ax,
    frames: Sequence[Mapping[str, np.ndarray]],
    *,
    colors="black",
    names: Sequence[str] | None = None,
    label: str = "task frame {name}",
    length: float | None = None,
    markersize: float = 8.0,
):
    """Mark task frames: a marker at each position, an arrow along each x axis.

    Parameters
    ----------
    ax : Axes
        The position's axes (2-D or 3-D); a frame's first two or three values
        are its position there.
    frames : sequence of mapping of str to array-like
        The frames of each demonstration (``Demonstration.frames``), or of
        one path: name to pose, a position (as many values as the position)
        or 7 values (x, y, z, then a unit quaternion w, x, y, z).
    colors : str or sequence of str, default="black"
        One colour for all, or one per item of ``frames`` (a demonstration's
        line colour).
    names : sequence of str, optional
        The frame names in the order that gives their marker styles
        (:data:`FRAME_MARKERS`); default the names in ``frames``, in order
        of appearance. Give the same to mark several sets alike.
    label : str, default="task frame {name}"
        The legend label of each frame name (one entry per name).
    length : float, optional
        The arrows' length; default a twelfth of the largest extent of what
        the axes show.
    markersize : float, default=8.0

    Returns
    -------
    ax : Axes

    Examples
    --------
    >>> import numpy as np
    >>> from ndlfd.plot import new_figure
    >>> _, (ax,) = new_figure(1)
    >>> turned = [0.5, 0.0, 0.0, np.sqrt(0.5), 0.0, 0.0, np.sqrt(0.5)]
    >>> frames = [{"object": turned, "place": [0.0, 1.0]}]
    >>> ax = plot_frames(ax, frames, length=0.25)
    >>> [(ln.get_marker(), ln.get_label()) for ln in ax.lines]
    [('s', 'task frame object'), ('^', 'task frame place')]
    >>> arrow = ax.collections[0]  # turned 90 deg about z: x now along y
    >>> [round(float(v), 6) + 0.0 for v in (arrow.U[0], arrow.V[0])]
    [0.0, 0.25]
    """
    frames = [dict(f) for f in frames]
    if isinstance(colors, str):
        colors = [colors] * len(frames)
    if len(colors) != len(frames):
        raise ValidationError(
            f"plot_frames needs one colour per item of frames ({len(frames)});"
            f" got {len(colors)}"
        )
    seen = list(dict.fromkeys(n for f in frames for n in f))
    names = seen if names is None else list(names)
    missing = [n for n in seen if n not in names]
    if missing:
        raise ValidationError(
            f"names must hold every frame's name; {', '.join(missing)} missing"
        )
    dims = 3 if ax.name == "3d" else 2
    length = _extent(ax) / 12 if length is None else float(length)
    for name in seen:
        marker, labelled = frame_marker(name, names), False
        for f, color in zip(frames, colors, strict=True):
            if name not in f:
                continue
            pose = np.asarray(f[name], dtype=float).ravel()
            if pose.size < dims:
                raise ValidationError(
                    f"frame {name} must have at least {dims} values to draw on"
                    f" {dims}-D axes; got {pose.size}"
                )
            shown = "_nolegend_" if labelled else label.format(name=name)
            ax.plot(*pose[:dims, None], marker, color=color, mec="black", mew=0.8,
                    ms=markersize, linestyle="none", zorder=4, label=shown)  # fmt: skip
            labelled = True
            if pose.size == 7:
                _arrow(ax, pose[:3], _x_axes(pose[None, 3:])[0], length, color)
    return ax


def _arrow(ax, origin: np.ndarray, direction: np.ndarray, length, color) -> None:
    """A short arrow from ``origin`` along ``direction`` (its plotted part)."""
    if ax.name == "3d":
        ax.quiver(*origin, *(length * direction), color=color, lw=1.6,
                  arrow_length_ratio=0.3, zorder=4)  # fmt: skip
        return
    uv = length * direction[:2]
    if np.hypot(*uv) < 1e-3 * length:  # the x axis across the plane: no arrow
        return
    ax.quiver(*origin[:2], *uv, color=color, angles="xy", scale_units="xy",
              scale=1, width=0.006, zorder=4)  # fmt: skip
