"""ndlfd.plot as a package: its names, and matplotlib imported only when drawing."""

import subprocess
import sys

import pytest

import ndlfd
from ndlfd import MissingExtraError

#: ndlfd.plot's public names before it was split into a package (issue 41).
ALL = [
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
#: Public outside __all__, read by the command line, the jobs and the tests.
ALSO = [
    "DEMO_COLOR",
    "GEN_COLOR",
    "KEY_COLOR",
    "PALETTE",
    "ROUTE_COLORS",
    "TEST_COLOR",
    "TRIAD_COLORS",
    "band_polygons",
    "triad_indices",
]


def test_the_package_keeps_every_public_name():
    plot = ndlfd.plot
    assert plot.__all__ == ALL
    public = sorted(n for n in vars(plot) if not n.startswith("_"))
    # what is left are the private modules' names
    assert public == sorted(ALL + ALSO)
    for name in ALL:
        assert callable(getattr(plot, name)), name
        assert getattr(plot, name).__module__.startswith("ndlfd.plot._"), name


def test_importing_ndlfd_and_its_plot_module_imports_no_matplotlib():
    code = (
        "import sys, ndlfd, ndlfd.plot, ndlfd.cli\n"
        "print(sorted(m for m in sys.modules if m.split('.')[0] == 'matplotlib'))"
    )
    out = subprocess.run(
        [sys.executable, "-c", code], capture_output=True, text=True, check=True
    )
    assert out.stdout.strip() == "[]"


def test_a_figure_without_matplotlib_names_the_extra(monkeypatch):
    for name in [m for m in sys.modules if m.split(".")[0] == "matplotlib"]:
        monkeypatch.delitem(sys.modules, name)
    monkeypatch.setitem(sys.modules, "matplotlib", None)  # import now fails
    with pytest.raises(MissingExtraError, match=r'pip install "ndlfd\[plot\]"'):
        ndlfd.plot.new_figure(1)
    with pytest.raises(MissingExtraError, match="matplotlib"):
        ndlfd.plot.plot_channels([ndlfd.Demonstration.from_arrays([0.0, 1.0],
                                  joints=[[0.0], [1.0]])])  # fmt: skip
