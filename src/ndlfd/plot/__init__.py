"""Figures a person would rather look at than read (optional ``plot`` extra).

Everything here draws on :class:`matplotlib.figure.Figure` objects without
pyplot, so it works headless (no display, no backend switching) in scripts,
tests and the command line. Install the extra with ``pip install "ndlfd[plot]"``.
matplotlib is imported when a figure is made, never on ``import ndlfd``.

Conventions: demonstrations in one light colour, key points as dots, the start
as ``×`` and the goal as ``*``, the generated path in red over them, the test
demonstration dashed, sampled paths as thin red lines, orientation triads
with the x, y and z axes in red, green and blue (as RViz draws frames), and
task frames as markers in their demonstration's colour (:func:`plot_frames`).
"""

# public outside __all__, as before the split: the colours, where triads go,
# the band's polygons
from ._band import band_polygons as band_polygons
from ._band import plot_band
from ._boxes import plot_boxplot, plot_keypoint_counts
from ._channels import new_figure_beside, plot_channels
from ._figures import DEMO_COLOR as DEMO_COLOR
from ._figures import GEN_COLOR as GEN_COLOR
from ._figures import KEY_COLOR as KEY_COLOR
from ._figures import PALETTE as PALETTE
from ._figures import ROUTE_COLORS as ROUTE_COLORS
from ._figures import TEST_COLOR as TEST_COLOR
from ._figures import TRIAD_COLORS as TRIAD_COLORS
from ._figures import new_figure, new_grid, save_figure
from ._frames import plot_frames
from ._paths import plot_comparison, plot_demos, plot_path, plot_samples
from ._triads import plot_triads
from ._triads import triad_indices as triad_indices

__all__ = [
    "new_figure",
    "new_figure_beside",
    "new_grid",
    "plot_band",
    "plot_boxplot",
    "plot_channels",
    "plot_comparison",
    "plot_demos",
    "plot_frames",
    "plot_keypoint_counts",
    "plot_path",
    "plot_samples",
    "plot_triads",
    "save_figure",
]
